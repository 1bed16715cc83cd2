#include "scene_graph_tracker/semap/bridge.hpp"

#include <functional>
#include <set>

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

::ros::Time toTime(const std::optional<double>& s) { return s ? ::ros::Time(*s) : ::ros::Time(0); }

double stampOf(const std_msgs::Header& h) {
  return (h.stamp.isZero() ? ::ros::Time::now() : h.stamp).toSec();
}

}  // namespace

semap::ClassShape classShape(const ObjectClass& c, std::size_t max_points) {
  semap::ClassShape s;
  s.name = c.name;
  s.box = c.box.cast<double>();
  if (c.mesh && !c.mesh->vertices.empty()) {
    const std::size_t n = c.mesh->vertices.size(),
                      step = std::max<std::size_t>(1, n / std::max<std::size_t>(max_points, 1));
    for (std::size_t i = 0; i < n && s.hull_points.size() < max_points; i += step)
      s.hull_points.push_back(c.mesh->vertices[i].cast<double>());
  }
  return s;
}

namespace {

void checkMessageSize(std::size_t n) {
  if (n > kMaxFrameObjects)
    throw ConversionError(std::to_string(n) + " objects in one message (at most " +
                          std::to_string(kMaxFrameObjects) + ")");
}

void checkId(const std::string& id, std::set<std::string>& seen) {
  if (id.empty()) throw ConversionError("an object with an empty id");
  if (!seen.insert(id).second) throw ConversionError("object id '" + id + "' appears twice");
}

}  // namespace

std::map<std::string, Eigen::Isometry3d> worldPoses(const scene_graph_tracker::SceneGraph& graph) {
  checkMessageSize(graph.nodes.size());
  std::map<std::string, const scene_graph_tracker::SceneGraphNode*> nodes;
  for (const auto& n : graph.nodes) nodes[n.id] = &n;
  std::map<std::string, Eigen::Isometry3d> world;
  for (const auto& start : graph.nodes) {
    // Walk up to a resolved node or the root, then compose back down: no recursion, so a long
    // parent chain cannot overflow the stack.
    std::vector<const scene_graph_tracker::SceneGraphNode*> chain;
    for (const auto* n = &start; n && !world.count(n->id);) {
      if (chain.size() > nodes.size())
        throw ConversionError("scene graph: parent cycle through '" + n->id + "'");
      chain.push_back(n);
      const auto parent = nodes.find(n->parent);
      n = parent != nodes.end() && n->parent != n->id ? parent->second : nullptr;
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const auto parent = world.find((*it)->parent);
      const Eigen::Isometry3d T_parent = parent != world.end() && (*it)->parent != (*it)->id
                                             ? parent->second
                                             : Eigen::Isometry3d::Identity();
      world[(*it)->id] = T_parent * toEigen((*it)->T_parent_node);
    }
  }
  return world;
}

semap::Frame frameFromSceneGraph(const scene_graph_tracker::SceneGraph& graph, double stamp,
                                 const ShapeLookup& shape) {
  const auto world = worldPoses(graph);
  semap::Frame frame;
  frame.stamp = stamp;
  std::set<std::string> seen;
  for (const auto& n : graph.nodes) {
    checkId(n.id, seen);
    if (auto s = shape(n.class_name)) frame.objects.push_back({n.id, s, n.parent, world.at(n.id)});
  }
  return frame;
}

semap::Frame frameFromTrackedObjects(const scene_graph_tracker::TrackedObjectArray& objects,
                                     double stamp, const ShapeLookup& shape) {
  checkMessageSize(objects.objects.size());
  semap::Frame frame;
  frame.stamp = stamp;
  std::set<std::string> seen;
  for (const auto& o : objects.objects) {
    checkId(o.id, seen);
    const Eigen::Isometry3d T = toEigen(o.pose.pose);
    if (auto s = shape(o.class_name)) frame.objects.push_back({o.id, s, o.parent, T});
  }
  return frame;
}

SemapBridge::SemapBridge(::ros::NodeHandle nh, ::ros::NodeHandle pnh) {
  settings_.host = pnh.param<std::string>("db_host", settings_.host);
  settings_.port = pnh.param("db_port", settings_.port);
  settings_.user = pnh.param<std::string>("db_user", settings_.user);
  settings_.password = pnh.param<std::string>("db_password", settings_.password);
  settings_.dbname = pnh.param<std::string>("db_name", settings_.dbname);
  settings_.connect_timeout_s = pnh.param("connect_timeout", settings_.connect_timeout_s);
  settings_.sql_dir = pnh.param<std::string>("sql_dir", "");
  settings_.factor = pnh.param("factor", settings_.factor);
  settings_.on_max_distance = pnh.param("on_max_distance", settings_.on_max_distance);
  settings_.tolerance = pnh.param("tolerance", settings_.tolerance);
  semap::WriterOptions options;
  options.queue_size = static_cast<std::size_t>(
      std::max(1, pnh.param("queue_size", static_cast<int>(options.queue_size))));
  options.backoff_min_s = pnh.param("backoff_min", options.backoff_min_s);
  options.backoff_max_s = pnh.param("backoff_max", options.backoff_max_s);
  options.flush_timeout_s = pnh.param("flush_timeout", options.flush_timeout_s);
  write_period_ = pnh.param("write_period", write_period_);
  relation_period_ = pnh.param("relation_period", relation_period_);
  std::string catalog = pnh.param<std::string>("catalog", "");
  if (catalog.empty()) catalog = std::string(SGT_SOURCE_DIR) + "/config/objects.yaml";
  catalog_ = loadObjectCatalog(catalog, pnh.param<std::string>("mesh_dir", ""));

  writer_ = std::make_unique<semap::SemapWriter>(settings_, options);
  const std::string source = pnh.param<std::string>("source", "scene_graph");
  if (source == "tracked_objects")
    sub_ = nh.subscribe("tracked_objects", 10, &SemapBridge::onTrackedObjects, this);
  else
    sub_ = nh.subscribe("scene_graph", 10, &SemapBridge::onSceneGraph, this);
  services_.push_back(
      pnh.advertiseService("query_relations", &SemapBridge::onQueryRelations, this));
  services_.push_back(pnh.advertiseService("objects_on", &SemapBridge::onObjectsOn, this));
  services_.push_back(pnh.advertiseService("objects_in", &SemapBridge::onObjectsIn, this));
  services_.push_back(
      pnh.advertiseService("directional_relations", &SemapBridge::onDirectional, this));
  services_.push_back(pnh.advertiseService("where_was", &SemapBridge::onWhereWas, this));
  services_.push_back(pnh.advertiseService("relation_since", &SemapBridge::onRelationSince, this));
  ROS_INFO("semap_bridge: %s -> postgresql://%s@%s:%d/%s (queue %zu frames, %zu classes)",
           sub_.getTopic().c_str(), settings_.user.c_str(), settings_.host.c_str(), settings_.port,
           settings_.dbname.c_str(), options.queue_size, catalog_.size());
}

std::shared_ptr<const semap::ClassShape> SemapBridge::shape(const std::string& class_name) {
  if (const auto it = shapes_.find(class_name); it != shapes_.end()) return it->second;
  if (!catalog_.contains(class_name)) {
    ROS_WARN_THROTTLE(10.0,
                      "semap_bridge: class '%s' is not in the catalog: its objects are not stored",
                      class_name.c_str());
    return nullptr;
  }
  return shapes_[class_name] =
             std::make_shared<const semap::ClassShape>(classShape(catalog_.get(class_name)));
}

void SemapBridge::push(semap::Frame frame) {
  if (last_write_ && frame.stamp >= *last_write_ && frame.stamp - *last_write_ < write_period_)
    return;
  if (last_write_ && frame.stamp < *last_write_) {
    ROS_WARN("semap_bridge: time went back by %.3f s (bag restarted?)", *last_write_ - frame.stamp);
    last_relations_.reset();
  }
  last_write_ = frame.stamp;
  frame.update_relations = !last_relations_ || frame.stamp - *last_relations_ >= relation_period_;
  if (frame.update_relations) last_relations_ = frame.stamp;
  writer_->push(std::move(frame));
}

void SemapBridge::onSceneGraph(const scene_graph_tracker::SceneGraphConstPtr& msg) {
  accept([&](const ShapeLookup& shape) {
    return frameFromSceneGraph(*msg, stampOf(msg->header), shape);
  });
}

void SemapBridge::onTrackedObjects(const scene_graph_tracker::TrackedObjectArrayConstPtr& msg) {
  accept([&](const ShapeLookup& shape) {
    return frameFromTrackedObjects(*msg, stampOf(msg->header), shape);
  });
}

// A malformed message is counted and skipped with a warning; it never stops the node.
void SemapBridge::accept(const std::function<semap::Frame(const ShapeLookup&)>& convert) {
  semap::Frame frame;
  try {
    frame = convert([this](const std::string& c) { return shape(c); });
  } catch (const std::exception& e) {
    ++malformed_;
    ROS_WARN_THROTTLE(5.0, "semap_bridge: skipping a malformed message (%zu so far): %s",
                      malformed_, e.what());
    return;
  }
  push(std::move(frame));
}

template <class Response, class F>
bool SemapBridge::answer(Response& res, F f) {
  std::lock_guard<std::mutex> lock(query_mutex_);
  try {
    if (!query_db_ || !query_db_->isOpen()) query_db_ = std::make_unique<semap::SemapDb>(settings_);
    f(*query_db_);
    res.success = true;
  } catch (const std::invalid_argument& e) {
    res.success = false, res.message = e.what();
  } catch (const std::exception& e) {
    query_db_.reset();  // reconnect on the next call
    res.success = false, res.message = std::string("semap database: ") + e.what();
    ROS_WARN_THROTTLE(5.0, "semap_bridge: query failed: %s", e.what());
  }
  return true;
}

bool SemapBridge::onQueryRelations(scene_graph_tracker::QueryRelations::Request& req,
                                   scene_graph_tracker::QueryRelations::Response& res) {
  return answer(res, [&](semap::SemapDb& db) {
    for (const semap::RelationRow& r :
         db.relations(req.subject, req.relation, req.object, req.mode)) {
      scene_graph_tracker::SemapRelation m;
      m.subject = r.subject, m.relation = r.relation, m.object = r.object,
      m.since = toTime(r.since);
      res.relations.push_back(m);
    }
  });
}

bool SemapBridge::onObjectsOn(scene_graph_tracker::ObjectsOn::Request& req,
                              scene_graph_tracker::ObjectsOn::Response& res) {
  return answer(res, [&](semap::SemapDb& db) { res.ids = db.objectsOn(req.reference, req.mode); });
}

bool SemapBridge::onObjectsIn(scene_graph_tracker::ObjectsIn::Request& req,
                              scene_graph_tracker::ObjectsIn::Response& res) {
  return answer(res, [&](semap::SemapDb& db) { res.ids = db.objectsIn(req.reference, req.mode); });
}

bool SemapBridge::onDirectional(scene_graph_tracker::DirectionalRelations::Request& req,
                                scene_graph_tracker::DirectionalRelations::Response& res) {
  return answer(res, [&](semap::SemapDb& db) {
    res.relations = db.directionalRelations(req.a, req.b, req.mode);
  });
}

bool SemapBridge::onWhereWas(scene_graph_tracker::WhereWas::Request& req,
                             scene_graph_tracker::WhereWas::Response& res) {
  return answer(res, [&](semap::SemapDb& db) {
    const auto p = db.whereWas(req.id, req.stamp.toSec());
    res.found = p.has_value();
    if (!p) return void(res.message = "no pose of '" + req.id + "' at or before that time");
    res.pose_stamp = ::ros::Time(p->stamp), res.parent = p->parent,
    res.pose = toPose(p->T_world_object);
  });
}

bool SemapBridge::onRelationSince(scene_graph_tracker::RelationSince::Request& req,
                                  scene_graph_tracker::RelationSince::Response& res) {
  return answer(res, [&](semap::SemapDb& db) {
    const semap::SinceAnswer a = db.relationSince(req.subject, req.relation, req.object, req.mode);
    res.holds = a.holds, res.since_known = a.since.has_value(), res.since = toTime(a.since);
  });
}

}  // namespace sgt::ros
