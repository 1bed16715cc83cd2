#include "scene_graph_tracker/semap/bridge.hpp"

#include <cmath>
#include <functional>
#include <set>

#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/diagnostics.hpp"

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

// Names are stored as they are, as query parameters (never spliced into SQL). They must be text
// the database can hold and index: UTF-8 without NUL (libpq would cut the name there), and at most
// kMaxNameBytes (an index entry holds a few kB).
bool validUtf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80           ? 1
                          : (c >> 5) == 0x6  ? 2
                          : (c >> 4) == 0xE  ? 3
                          : (c >> 3) == 0x1E ? 4
                                             : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return false;
    i += n;
  }
  return true;
}

void checkName(const char* what, const std::string& name) {
  if (name.size() > kMaxNameBytes)
    throw ConversionError(std::string(what) + " of " + std::to_string(name.size()) +
                          " bytes (at most " + std::to_string(kMaxNameBytes) + ")");
  if (name.find('\0') != std::string::npos)
    throw ConversionError(std::string(what) + " '" + name.c_str() + "...' holds a NUL byte");
  if (!validUtf8(name)) throw ConversionError(std::string(what) + " is not UTF-8");
}

void checkObject(const std::string& id, const std::string& class_name, const std::string& parent,
                 std::set<std::string>& seen) {
  if (id.empty()) throw ConversionError("an object with an empty id");
  checkName("object id", id), checkName("class name", class_name), checkName("parent id", parent);
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
    checkObject(n.id, n.class_name, n.parent, seen);
    if (auto s = shape(n.class_name)) frame.objects.push_back({n.id, s, n.parent, world.at(n.id)});
  }
  return frame;
}

semap::Frame forRobot(semap::Frame frame, const std::string& robot) {
  if (robot.empty()) return frame;
  checkName("robot id", robot);
  if (robot.find('/') != std::string::npos)
    throw ConversionError("robot id '" + robot + "' holds a '/'");
  std::set<std::string> ids;
  for (const auto& o : frame.objects) ids.insert(o.id);
  for (auto& o : frame.objects) {
    if (ids.count(o.parent)) o.parent = robot + "/" + o.parent;
    o.id = robot + "/" + o.id;
  }
  frame.robot = robot;
  return frame;
}

semap::Frame frameFromTrackedObjects(const scene_graph_tracker::TrackedObjectArray& objects,
                                     double stamp, const ShapeLookup& shape) {
  checkMessageSize(objects.objects.size());
  semap::Frame frame;
  frame.stamp = stamp;
  std::set<std::string> seen;
  for (const auto& o : objects.objects) {
    checkObject(o.id, o.class_name, o.parent, seen);
    const Eigen::Isometry3d T = toEigen(o.pose.pose);
    if (auto s = shape(o.class_name)) frame.objects.push_back({o.id, s, o.parent, T});
  }
  return frame;
}

namespace {

semap::DbSettings dbSettings(const ::ros::NodeHandle& pnh) {
  semap::DbSettings s;
  s.host = pnh.param<std::string>("db_host", s.host);
  s.port = pnh.param("db_port", s.port);
  s.user = pnh.param<std::string>("db_user", s.user);
  s.password = pnh.param<std::string>("db_password", s.password);
  s.passfile = pnh.param<std::string>("db_passfile", s.passfile);
  s.dbname = pnh.param<std::string>("db_name", s.dbname);
  s.connect_timeout_s = pnh.param("connect_timeout", s.connect_timeout_s);
  s.tcp_timeout_s = pnh.param("tcp_timeout", s.tcp_timeout_s);
  s.statement_timeout_s = pnh.param("statement_timeout", s.statement_timeout_s);
  s.sql_dir = pnh.param<std::string>("sql_dir", "");
  s.factor = pnh.param("factor", s.factor);
  s.on_max_distance = pnh.param("on_max_distance", s.on_max_distance);
  s.tolerance = pnh.param("tolerance", s.tolerance);
  if (!s.password.empty())
    ROS_WARN(
        "semap_bridge: ~db_password is readable by every node on this ROS master; prefer "
        "~db_passfile (a 0600 libpq password file, as scripts/semap-db.sh writes)");
  return s;
}

semap::WriterOptions writerOptions(const ::ros::NodeHandle& pnh) {
  semap::WriterOptions o;
  o.queue_size = static_cast<std::size_t>(
      std::max(1, pnh.param("queue_size", static_cast<int>(o.queue_size))));
  o.backoff_min_s = pnh.param("backoff_min", o.backoff_min_s);
  o.backoff_max_s = pnh.param("backoff_max", o.backoff_max_s);
  o.flush_timeout_s = pnh.param("flush_timeout", o.flush_timeout_s);
  o.history_retention_s = pnh.param("history_retention", o.history_retention_s);
  o.prune_period_s = pnh.param("prune_period", o.prune_period_s);
  const std::string furniture = pnh.param<std::string>("furniture", "");
  if (!furniture.empty())
    for (const relations::Entity& f : relations::loadFurniture(furniture))
      o.fixed_objects.push_back({f.name,
                                 Eigen::AlignedBox3d(-f.box.half_extents, f.box.half_extents),
                                 f.box.T_world_box});
  return o;
}

}  // namespace

SemapBridge::SemapBridge(::ros::NodeHandle nh, ::ros::NodeHandle pnh)
    : settings_(dbSettings(pnh)), service_spinner_(1, &service_queue_) {
  const semap::WriterOptions options = writerOptions(pnh);
  map_frame_ = pnh.param<std::string>("map_frame", map_frame_);
  robot_id_ = pnh.param<std::string>("robot_id", "");
  forRobot({}, robot_id_);  // a robot id that cannot be stored fails here, not on every message
  write_period_ = pnh.param("write_period", write_period_);
  relation_period_ = pnh.param("relation_period", relation_period_);
  std::string catalog = pnh.param<std::string>("catalog", "");
  if (catalog.empty()) catalog = "package://scene_graph_tracker/config/objects.yaml";
  catalog_ = loadObjectCatalog(catalog, pnh.param<std::string>("mesh_dir", ""));

  writer_ = std::make_unique<semap::SemapWriter>(settings_, options);
  const std::string source = pnh.param<std::string>("source", "scene_graph");
  // The subscription's own thread only converts and queues (never waits for the database); the
  // services run on a second thread, so a slow query cannot make the subscriber drop messages.
  const int queue = std::max(1, pnh.param("subscriber_queue", 100));
  if (source == "tracked_objects")
    sub_ = nh.subscribe("tracked_objects", queue, &SemapBridge::onTrackedObjects, this);
  else
    sub_ = nh.subscribe("scene_graph", queue, &SemapBridge::onSceneGraph, this);
  ::ros::NodeHandle spnh(pnh);
  spnh.setCallbackQueue(&service_queue_);
  services_.push_back(
      spnh.advertiseService("query_relations", &SemapBridge::onQueryRelations, this));
  services_.push_back(spnh.advertiseService("objects_on", &SemapBridge::onObjectsOn, this));
  services_.push_back(spnh.advertiseService("objects_in", &SemapBridge::onObjectsIn, this));
  services_.push_back(
      spnh.advertiseService("directional_relations", &SemapBridge::onDirectional, this));
  services_.push_back(spnh.advertiseService("where_was", &SemapBridge::onWhereWas, this));
  services_.push_back(spnh.advertiseService("relation_since", &SemapBridge::onRelationSince, this));
  service_spinner_.start();
  diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5);
  diagnostics_timer_ = nh.createWallTimer(
      ::ros::WallDuration(1.0), [this](const ::ros::WallTimerEvent&) { publishDiagnostics(); });
  ROS_INFO(
      "semap_bridge: %s -> postgresql://%s@%s:%d/%s (queue %zu frames, %zu classes, %zu pieces of "
      "furniture)",
      sub_.getTopic().c_str(), settings_.user.c_str(), settings_.host.c_str(), settings_.port,
      settings_.dbname.c_str(), options.queue_size, catalog_.size(), options.fixed_objects.size());
}

SemapBridge::~SemapBridge() { service_spinner_.stop(); }

BridgeCounts SemapBridge::counts() const {
  std::lock_guard<std::mutex> lock(counts_mutex_);
  BridgeCounts c = counts_;
  c.writer = writer_->stats();
  return c;
}

// One status, "scene_graph_tracker: semap_bridge": every counter, WARN while frames are lost or the
// database is unreachable. Identity: pushed = written + dropped + rejected + pending.
void SemapBridge::publishDiagnostics() {
  const BridgeCounts c = counts();
  const bool ok = c.writer.connected && c.malformed == 0 && c.missed == 0 &&
                  c.writer.dropped == 0 && c.writer.rejected == 0;
  const std::string message = !c.writer.connected ? "database unreachable, frames queued"
                              : ok                ? "storing"
                                   : "storing; some messages were not stored (see the counts)";
  const semap::WriterStats& w = c.writer;
  diagnostics_pub_.publish(diagnostics("semap_bridge", settings_.dbname, ok, message,
                                       {{"messages_in", c.messages_in},
                                        {"messages_missed", c.missed},
                                        {"messages_malformed", c.malformed},
                                        {"throttled", c.throttled},
                                        {"pushed", w.pushed},
                                        {"written", w.written},
                                        {"dropped", w.dropped},
                                        {"rejected", w.rejected},
                                        {"pending", w.pending},
                                        {"duplicate_frames", w.duplicate_frames},
                                        {"duplicate_rows", w.duplicate_rows},
                                        {"pose_rows", w.pose_rows},
                                        {"pruned_rows", w.pruned_rows},
                                        {"connects", w.connects},
                                        {"failed_attempts", w.failed_attempts},
                                        {"last_outage_s", w.last_outage_s}}));
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
  if (last_write_ && frame.stamp >= *last_write_ && frame.stamp - *last_write_ < write_period_) {
    std::lock_guard<std::mutex> lock(counts_mutex_);
    ++counts_.throttled;  // by ~write_period: not lost, just not stored
    return;
  }
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
  accept(msg->header, [&](const ShapeLookup& shape) {
    return frameFromSceneGraph(*msg, stampOf(msg->header), shape);
  });
}

void SemapBridge::onTrackedObjects(const scene_graph_tracker::TrackedObjectArrayConstPtr& msg) {
  accept(msg->header, [&](const ShapeLookup& shape) {
    return frameFromTrackedObjects(*msg, stampOf(msg->header), shape);
  });
}

// A malformed message is counted and skipped with a warning; it never stops the node.
void SemapBridge::accept(const std_msgs::Header& header,
                         const std::function<semap::Frame(const ShapeLookup&)>& convert) {
  countSequence(header.seq);
  semap::Frame frame;
  try {
    frame = forRobot(convert([this](const std::string& c) { return shape(c); }), robot_id_);
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(counts_mutex_);
    ++counts_.malformed;
    ROS_WARN_THROTTLE(5.0, "semap_bridge: skipping a malformed message (%zu so far): %s",
                      counts_.malformed, e.what());
    return;
  }
  push(std::move(frame));
}

// The tracker numbers its messages (header.seq from 1): a gap is a message lost before the bridge
// (e.g. in a full subscriber queue). Publishers that leave seq at 0 are not checked.
void SemapBridge::countSequence(std::uint32_t seq) {
  std::lock_guard<std::mutex> lock(counts_mutex_);
  ++counts_.messages_in;
  if (seq != 0 && last_seq_ != 0 && seq > last_seq_ + 1) {
    counts_.missed += seq - last_seq_ - 1;
    ROS_WARN_THROTTLE(5.0, "semap_bridge: %u messages lost before the bridge (%zu so far)",
                      seq - last_seq_ - 1, counts_.missed);
  }
  last_seq_ = seq;
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
  std::optional<Eigen::Vector2d> viewer;
  if (!req.viewer_frame.empty()) {
    try {
      const Eigen::Vector3d p = toEigen(tf_buffer_
                                            .lookupTransform(map_frame_, req.viewer_frame,
                                                             ::ros::Time(0), ::ros::Duration(0.5))
                                            .transform)
                                    .translation();
      viewer = p.head<2>();
    } catch (const tf2::TransformException& e) {
      res.success = false, res.message = "viewer frame: " + std::string(e.what());
      return true;
    }
  }
  return answer(res, [&](semap::SemapDb& db) {
    res.relations = db.directionalRelations(req.a, req.b, req.mode, viewer);
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
