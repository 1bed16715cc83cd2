#include "scene_graph_tracker/ros/tracker_nodelet.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <scene_graph_tracker/SceneGraph.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <visualization_msgs/MarkerArray.h>

#include <boost/bind/bind.hpp>
#include <map>
#include <optional>
#include <pluginlib/class_list_macros.hpp>

#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/map_markers.hpp"
#include "scene_graph_tracker/ros/parameters.hpp"
#include "scene_graph_tracker/ros/relation_markers.hpp"
#include "scene_graph_tracker/ros/track_id_store.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"
#include "scene_graph_tracker/util/heap_trim.hpp"

namespace sgt::ros {
namespace {

// How often the manager's freed heap goes back to the system (util/heap_trim.hpp): a trim costs
// a few milliseconds, and without it the RSS keeps the high-water mark of every image burst.
constexpr double kHeapTrimPeriod = 10.0;

std_msgs::ColorRGBA colour(TrackState s) {
  std_msgs::ColorRGBA c;
  c.a = 0.85f;
  switch (s) {
    case TrackState::kTentative:
      c.r = 1.0f, c.g = 0.8f, c.b = 0.1f;
      break;
    case TrackState::kConfirmed:
      c.r = 0.1f, c.g = 0.8f, c.b = 0.2f;
      break;
    default:
      c.r = c.g = c.b = 0.55f;
      break;
  }
  return c;
}

}  // namespace

// A failed start (a bad parameter, a map or catalog that does not load) throws to the nodelet
// loader, which then drops this nodelet's callback queues before it destroys the nodelet. The
// subscriptions made so far are shut down first: destroyed after their queue, they take down
// the whole manager (SIGSEGV in ros::Subscription::removeCallback).
void TrackerNodelet::onInit() {
  try {
    initialize();
  } catch (...) {
    shutDownInterfaces();
    throw;
  }
}

void TrackerNodelet::shutDownInterfaces() {
  depth_sub_.shutdown();
  info_sub_.unsubscribe();
  for (::ros::Subscriber* s : {&cloud_sub_, &scan_sub_, &hypotheses_sub_, &initialpose_sub_})
    s->shutdown();
  for (::ros::ServiceServer* s : {&reset_srv_, &add_srv_, &remove_srv_}) s->shutdown();
  reconfigure_.reset();
  tf_listener_.reset();
}

void TrackerNodelet::initialize() {
  ::ros::NodeHandle& nh = getNodeHandle();
  ::ros::NodeHandle& pnh = getPrivateNodeHandle();
  // Every parameter of the schema (pipeline/parameter_schema.hpp) by its name; the others keep
  // the option structs' defaults. A bad value stops the nodelet (the loader does not say why).
  params::TrackerParameters p;
  std::vector<std::string> unknown;
  try {
    unknown = readParameters(pnh, params::trackerSchema(), p);
  } catch (const params::ParameterError& e) {
    NODELET_FATAL("tracker: %s", e.what());
    throw;
  }
  for (const std::string& name : unknown)
    NODELET_WARN("tracker: ~%s is no parameter of the tracker (ignored; see doc/parameters.md)",
                 name.c_str());
  map_frame_ = p.node.map_frame, odom_frame_ = p.node.odom_frame, base_frame_ = p.node.base_frame;
  publish_object_tf_ = p.node.publish_object_tf;
  setUpLocalization(p.node, p.pipeline);  // external: localize off, dynamic_reconfigure says so
  const PipelineOptions& o = p.pipeline;
  const std::string& catalog_path = p.node.catalog;
  const std::string& mesh_dir = p.node.mesh_dir;
  // The static world: a mesh or URDF, and optionally its furniture (relations/furniture.hpp); for
  // the simulated building, tools/write_map writes both.
  const std::string& map_path = p.node.static_map;
  const std::string& furniture_path = p.node.furniture;
  if (map_path.empty()) {
    NODELET_FATAL("tracker: ~static_map is required (a mesh file or a URDF of the static world)");
    throw std::runtime_error("tracker: ~static_map is not set");
  }
  auto catalog = std::make_shared<ObjectCatalog>(loadObjectCatalog(catalog_path, mesh_dir));
  auto map = std::make_shared<TriangleMesh>(loadStaticMap(map_path));
  pipeline_ = std::make_unique<FramePipeline>(catalog, map, o);
  if (!furniture_path.empty()) pipeline_->setFurniture(relations::loadFurniture(furniture_path));
  track_ids_ = TrackIdStore(p.node.track_id_file);
  try {
    pipeline_->continueTrackNumbers(track_ids_.load());
    saved_track_numbers_ = pipeline_->lastTrackNumbers();
  } catch (const TrackIdStoreError& e) {
    NODELET_ERROR("tracker: %s; track ids start at 1 and may repeat earlier runs' ids", e.what());
  }
  NODELET_INFO(
      "tracker: %zu classes from %s, static map %s (%zu triangles), %zu pieces of furniture",
      catalog->size(), catalog_path.c_str(), map_path.c_str(), map->triangleCount(),
      pipeline_->furniture().size());

  // Before any subscription: a callback may come before onInit returns.
  hypothesis_wait_ = std::make_unique<HypothesisWait>(p.node.hypothesis_max_wait);
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>(::ros::Duration(30.0));
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  stamps_ = StampOrder(p.node.max_time_jitter);
  assembler_ = std::make_unique<FrameAssembler>(
      assemblerOptions(p.node),
      [this](const std::string& target, const std::string& source, const ::ros::Time& t) {
        return toEigen(tf_buffer_->lookupTransform(target, source, t).transform);  // no wait
      });
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  objects_pub_ = pnh.advertise<scene_graph_tracker::TrackedObjectArray>("tracked_objects", 5);
  graph_pub_ = pnh.advertise<scene_graph_tracker::SceneGraph>("scene_graph", 5);
  unassigned_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("unassigned_points", 2);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 2);
  map_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("map_markers", 1, true);
  map_markers_pub_.publish(mapMarkers(*map, pipeline_->furniture(), map_frame_));
  diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5);
  depth_sub_.subscribe(nh, "depth/image", 3, p.node.depth_transport,
                       [this](const std::string& text) { onUndecodable(text); });
  NODELET_INFO("tracker: depth images: %s", depth_sub_.description().c_str());
  info_sub_.subscribe(nh, "depth/camera_info", 3);
  sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(SyncPolicy(5), depth_sub_,
                                                                      info_sub_);
  sync_->registerCallback(boost::bind(&TrackerNodelet::onDepth, this, boost::placeholders::_1,
                                      boost::placeholders::_2));
  cloud_sub_ = nh.subscribe("points", 2, &TrackerNodelet::onCloud, this);
  scan_sub_ = nh.subscribe("scan", 2, &TrackerNodelet::onLaserScan, this);
  hypotheses_sub_ = nh.subscribe("pose_hypotheses", 10, &TrackerNodelet::onHypotheses, this);
  if (p.node.hypothesis_max_wait > 0.0)
    hypothesis_wait_timer_ = nh.createWallTimer(
        ::ros::WallDuration(p.node.hypothesis_max_wait / 2), [this](const ::ros::WallTimerEvent&) {
          processAll(hypothesis_wait_->expired(::ros::WallTime::now()));
        });
  // Run-time parameters start from the values loaded above (config/tracker.yaml).
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<scene_graph_tracker::TrackerConfig>>(
      reconfigure_mutex_, pnh);
  scene_graph_tracker::TrackerConfig initial = scene_graph_tracker::TrackerConfig::__getDefault__();
  dynamic_reconfigure::Config values;
  initial.__toMessage__(values);
  toReconfigure(params::trackerSchema(), p, values);
  if (!initial.__fromMessage__(values))
    throw params::ParameterError("cfg/Tracker.cfg does not match the schema");
  reconfigure_->updateConfig(initial);
  reconfigure_->setCallback(boost::bind(&TrackerNodelet::onReconfigure, this,
                                        boost::placeholders::_1, boost::placeholders::_2));
  reset_srv_ = pnh.advertiseService("reset", &TrackerNodelet::onReset, this);
  add_srv_ = pnh.advertiseService("add_track", &TrackerNodelet::onAddTrack, this);
  remove_srv_ = pnh.advertiseService("remove_track", &TrackerNodelet::onRemoveTrack, this);
}

void TrackerNodelet::warn(const std::string& text) {
  if (warnings_.shouldLog(text)) NODELET_WARN("tracker: %s", text.c_str());
}

// A depth image that does not decode is a frame in, skipped.
void TrackerNodelet::onUndecodable(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.frames_in, ++counts_.skipped;
  warn("depth frame skipped: " + text);
}

void TrackerNodelet::onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  std::lock_guard<std::mutex> lock(mutex_);
  assembler_->addCloud(cloud);
}

void TrackerNodelet::onLaserScan(const sensor_msgs::LaserScanConstPtr& scan) {
  std::lock_guard<std::mutex> lock(mutex_);
  assembler_->addLaserScan(scan);
}

void TrackerNodelet::onHypotheses(const scene_graph_tracker::PoseHypothesisArrayConstPtr& msg) {
  if (!msg) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    assembler_->addHypotheses(msg);
  }
  processAll(hypothesis_wait_->addHypotheses(msg->header.stamp, ::ros::WallTime::now()));
}

void TrackerNodelet::onDepth(const sensor_msgs::ImageConstPtr& depth,
                             const sensor_msgs::CameraInfoConstPtr& info) {
  processAll(hypothesis_wait_->addDepth({depth, info}, ::ros::WallTime::now()));
}

void TrackerNodelet::processAll(const std::vector<DepthFrame>& frames) {
  for (const DepthFrame& f : frames) processDepth(f);
}

void TrackerNodelet::processDepth(const DepthFrame& f) {
  const sensor_msgs::ImageConstPtr& depth = f.image;
  const sensor_msgs::CameraInfoConstPtr& info = f.info;
  waitForTransforms(*depth);
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.frames_in;
  const ::ros::Time stamp = depth->header.stamp;
  const StampVerdict verdict = stamps_.peek(stamp.toSec());
  if (!inOrder(verdict)) return;
  AssembledFrame frame;
  try {
    frame = assembler_->assemble(*depth, *info);
  } catch (const std::exception& e) {
    ++counts_.skipped;
    warn(std::string("depth frame skipped: ") + e.what());
    publishDiagnostics(std::string("depth frame skipped: ") + e.what(), nullptr);
    return;
  }
  stamps_.take(stamp.toSec());  // a good frame: it sets the time line
  if (verdict == StampVerdict::kJumpBack) {
    ++counts_.time_jumps;
    NODELET_WARN("tracker: time went back (bag loop or clock reset): tracks reset");
    pipeline_->reset();
    assembler_->clear();  // clouds and hypotheses of the old time line
  }
  counts_.warnings += frame.warnings.size();
  for (const std::string& w : frame.warnings) warn(w);
  if (external_localization_) applyExternalLocalization(stamp);
  try {  // a failure costs this frame, never the nodelet manager
    const PipelineResult r = pipeline_->process(std::move(frame.frame));
    counts_.hypotheses_over_limits += r.hypotheses_over_limits;
    counts_.hypotheses_duplicate += r.hypotheses_duplicate;
    publish(r, stamp);
    saveTrackNumbers();
    ++counts_.processed;
    publishDiagnostics("", &r);
  } catch (const std::exception& e) {
    ++counts_.failed;
    warn(std::string("frame at ") + std::to_string(stamp.toSec()) + " failed: " + e.what());
    publishDiagnostics(std::string("frame failed: ") + e.what(), nullptr);
  }
  util::trimHeapEvery(kHeapTrimPeriod);
}

// Waits (up to 50 ms each) for the transforms an image needs before the lock is taken: TF often
// arrives a little after the image, and the other callbacks must not wait for it. The assembler
// then looks them up without waiting.
void TrackerNodelet::waitForTransforms(const sensor_msgs::Image& depth) {
  const ::ros::Duration wait(0.05);
  tf_buffer_->canTransform(odom_frame_, base_frame_, depth.header.stamp, wait);
  tf_buffer_->canTransform(odom_frame_, depth.header.frame_id, depth.header.stamp, wait);
  if (external_localization_)
    tf_buffer_->canTransform(map_frame_, odom_frame_, depth.header.stamp, wait);
}

// Written when a class got a new track: rare, and the file is tiny.
void TrackerNodelet::saveTrackNumbers() {
  if (!track_ids_.enabled() || pipeline_->lastTrackNumbers() == saved_track_numbers_) return;
  try {
    track_ids_.save(pipeline_->lastTrackNumbers());
    saved_track_numbers_ = pipeline_->lastTrackNumbers();
  } catch (const TrackIdStoreError& e) {
    ++counts_.warnings;
    warn(e.what());
  }
}

bool TrackerNodelet::inOrder(StampVerdict verdict) {
  switch (verdict) {
    case StampVerdict::kDuplicate:
      ++counts_.duplicates;
      warn("depth image with the stamp of the last one dropped");
      return false;
    case StampVerdict::kJitter:
      ++counts_.out_of_order;
      warn("depth image older than the last one dropped (out of order)");
      return false;
    default:
      return true;
  }
}

void TrackerNodelet::publish(const PipelineResult& r, const ::ros::Time& stamp) {
  std_msgs::Header header;
  header.stamp = stamp, header.frame_id = map_frame_;
  // Numbered from 1: a subscriber (semap_bridge) can count the messages it never received.
  header.seq = static_cast<std::uint32_t>(++published_);
  scene_graph_tracker::TrackedObjectArray objects;
  scene_graph_tracker::SceneGraph graph;
  objects.header = graph.header = header;
  for (const relations::Edge& e : r.relations) {
    scene_graph_tracker::SceneGraphEdge edge;
    edge.subject = e.subject, edge.relation = relations::relationName(e.relation),
    edge.object = e.object;
    graph.edges.push_back(edge);
  }
  std::map<std::string, const TrackedObject*> by_id;
  for (const TrackedObject& o : r.objects) by_id[o.id] = &o;
  for (const TrackedObject& o : r.objects) {
    // In the graph a track in / on another is that track's child (pose relative to it).
    const auto parent = by_id.find(o.parent);
    const TrackedObject* parent_object = parent != by_id.end() ? parent->second : nullptr;
    objects.objects.push_back(trackedObjectMessage(o, parent_object));
    graph.nodes.push_back(graphNodeMessage(o, parent_object));
    if (publish_object_tf_) {
      // TF follows the scene graph: a track in or on another hangs below it.
      geometry_msgs::TransformStamped tf;
      tf.header = header, tf.header.frame_id = graph.nodes.back().parent;
      tf.child_frame_id = o.id, tf.transform = graph.nodes.back().T_parent_node;
      tf_broadcaster_->sendTransform(tf);
    }
  }
  objects_pub_.publish(objects);
  graph_pub_.publish(graph);
  markers_pub_.publish(markers(r, header));
  if (publish_map_odom_ && r.localized) {  // only a converged localization speaks for the map
    geometry_msgs::TransformStamped tf;
    tf.header = header, tf.child_frame_id = odom_frame_;
    tf.transform = toTransform(r.T_map_odom);
    tf_broadcaster_->sendTransform(tf);
  }
  if (unassigned_pub_.getNumSubscribers() > 0) unassigned_pub_.publish(unassignedPoints(r, header));
}

scene_graph_tracker::TrackedObject TrackerNodelet::trackedObjectMessage(
    const TrackedObject& o, const TrackedObject* parent) const {
  scene_graph_tracker::TrackedObject t;
  t.id = o.id, t.class_name = o.class_name, t.state = toStateCode(o.state),
  t.parent = parent ? o.parent : map_frame_;
  t.pose.pose = toPose(o.T_map_object);
  for (int i = 0; i < 36; ++i) t.pose.covariance[i] = o.covariance(i / 6, i % 6);
  t.inlier_ratio = static_cast<float>(o.quality.inlier_ratio), t.inliers = o.quality.inliers;
  t.orientation_confidence = static_cast<float>(o.orientation_confidence);
  return t;
}

scene_graph_tracker::SceneGraphNode TrackerNodelet::graphNodeMessage(
    const TrackedObject& o, const TrackedObject* parent) const {
  scene_graph_tracker::SceneGraphNode n;
  n.id = o.id, n.class_name = o.class_name, n.parent = parent ? o.parent : map_frame_;
  n.T_parent_node = toTransform(
      parent ? Eigen::Isometry3d(parent->T_map_object.inverse() * o.T_map_object) : o.T_map_object);
  return n;
}

visualization_msgs::MarkerArray TrackerNodelet::markers(const PipelineResult& r,
                                                        const std_msgs::Header& header) const {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  int marker_id = 0;
  for (const TrackedObject& o : r.objects) {
    const ObjectClass& c = pipeline_->catalog().get(o.class_name);
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = "objects", m.id = marker_id++, m.type = visualization_msgs::Marker::MESH_RESOURCE;
    m.mesh_resource = c.mesh_uri;
    m.pose = toPose(o.T_map_object * c.T_object_mesh),
    m.scale.x = m.scale.y = m.scale.z = c.mesh_scale, m.color = colour(o.state);
    markers.markers.push_back(m);
    visualization_msgs::Marker box = m;
    box.ns = "boxes", box.id = marker_id++, box.type = visualization_msgs::Marker::CUBE,
    box.mesh_resource.clear();
    box.pose.orientation = toPose(o.T_map_object).orientation;  // c.box is in the object frame
    const Eigen::Vector3d centre = o.T_map_object * c.box.center().cast<double>();
    box.pose.position.x = centre.x(), box.pose.position.y = centre.y(),
    box.pose.position.z = centre.z();
    box.scale.x = c.box.sizes().x(), box.scale.y = c.box.sizes().y(),
    box.scale.z = c.box.sizes().z();
    box.color.a = 0.15f;
    markers.markers.push_back(box);
    visualization_msgs::Marker label = m;
    label.ns = "labels", label.id = marker_id++,
    label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    label.mesh_resource.clear();
    label.text = o.id + " (" + toString(o.state) + ")";
    label.pose.position.z += c.box.sizes().z() * 0.5 + 0.05;
    label.scale.z = 0.04, label.color.r = label.color.g = label.color.b = label.color.a = 1.0f;
    markers.markers.push_back(label);
  }
  // Relation edges: lines between box centres (tracks and furniture) with labels.
  std::map<std::string, Eigen::Vector3d> centres;
  for (const TrackedObject& o : r.objects)
    centres[o.id] =
        o.T_map_object * pipeline_->catalog().get(o.class_name).box.center().cast<double>();
  for (const relations::Entity& f : pipeline_->furniture())
    centres[f.name] = f.box.T_world_box.translation();
  for (auto& m : relationMarkers(r.relations, centres, map_frame_, header.stamp, marker_id))
    markers.markers.push_back(m);
  return markers;
}

sensor_msgs::PointCloud2 TrackerNodelet::unassignedPoints(const PipelineResult& r,
                                                          const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  std::size_t n = 0;
  for (const auto& p : r.presegmentation) n += p.unknown_points.size();
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(n);
  // An iterator on an empty cloud dereferences its empty data (undefined behaviour).
  if (n == 0) return cloud;
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const auto& p : r.presegmentation)
    for (const auto& q : p.unknown_points) *x = q.x(), *y = q.y(), *z = q.z(), ++x, ++y, ++z;
  return cloud;
}

void TrackerNodelet::publishDiagnostics(const std::string& problem, const PipelineResult* r) {
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ::ros::Time::now();
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "scene_graph_tracker: tracker", s.hardware_id = getName();
  s.level = problem.empty() ? diagnostic_msgs::DiagnosticStatus::OK
                            : diagnostic_msgs::DiagnosticStatus::WARN;
  s.message = problem.empty() ? "tracking" : problem;
  const auto kv = [&](const std::string& k, const std::string& v) {
    diagnostic_msgs::KeyValue x;
    x.key = k, x.value = v;
    s.values.push_back(x);
  };
  const Counts& c = counts_;
  for (const auto& [key, n] : {std::pair<const char*, std::size_t>{"frames_in", c.frames_in},
                               {"frames_processed", c.processed},
                               {"frames_skipped", c.skipped},
                               {"frames_failed", c.failed},
                               {"duplicate_stamps", c.duplicates},
                               {"out_of_order", c.out_of_order},
                               {"time_jumps", c.time_jumps},
                               {"input_warnings", c.warnings},
                               {"hypotheses_over_limits", c.hypotheses_over_limits},
                               {"hypotheses_duplicate", c.hypotheses_duplicate},
                               {"depth_received", depth_sub_.received()},
                               {"depth_lost_before", depth_sub_.lost()},
                               {"depth_superseded", depth_sub_.superseded()},
                               {"depth_waited_for_hypotheses", hypothesis_wait_->waited()},
                               {"depth_waited_in_vain", hypothesis_wait_->waitedInVain()}})
    kv(key, std::to_string(n));
  if (r) {
    kv("objects", std::to_string(r->objects.size()));
    const util::HeapUsage heap = util::heapUsage();  // the whole process: the manager's
    kv("heap_in_use_mb", std::to_string(heap.in_use_mb));
    kv("heap_free_held_mb", std::to_string(heap.free_held_mb));
    kv("frame_ms", std::to_string(r->times.total_ms));
    kv("depth_sigma_at_1m_mm", std::to_string(1000.0 * r->noise.depth_sigma_at_1m));
    if (external_localization_)
      kv("localized", external_pose_ok_ ? "yes (external)" : "no (no map to odom in TF)");
    else
      kv("localized", r->localized ? "yes" : "no");
    if (!external_localization_) {
      kv("localization_inlier_ratio", std::to_string(r->localization.inlier_ratio));
      kv("localization_rmse_mm", std::to_string(1000.0 * r->localization.rmse));
    }
  }
  array.status.push_back(s);
  diagnostics_pub_.publish(array);
}

void TrackerNodelet::onReconfigure(scene_graph_tracker::TrackerConfig& c, std::uint32_t) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Every run-time parameter of the schema, by its dynamic_reconfigure name.
  const params::TrackerParameters before{pipeline_->options(), {}};
  params::TrackerParameters after = before;
  dynamic_reconfigure::Config values;
  c.__toMessage__(values);
  fromReconfigure(params::trackerSchema(), values, after);
  if (external_localization_ && after.pipeline.localize) {
    after.pipeline.localize = false;
    warn("localize stays off: the localization is external");
  }
  std::string changed;
  for (const auto& p : params::trackerSchema())
    if (p.runtime && p.get(after) != p.get(before))
      changed += (changed.empty() ? "" : ", ") + p.name + " " + params::format(p, p.get(after));
  pipeline_->setOptions(after.pipeline);
  if (!changed.empty()) NODELET_INFO("tracker: reconfigured: %s", changed.c_str());
}

bool TrackerNodelet::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  pipeline_->reset();
  NODELET_INFO("tracker: reset");
  return true;
}

bool TrackerNodelet::onAddTrack(scene_graph_tracker::AddTrack::Request& req,
                                scene_graph_tracker::AddTrack::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    const Eigen::Isometry3d T_map_frame =
        req.pose.header.frame_id.empty() || req.pose.header.frame_id == map_frame_
            ? Eigen::Isometry3d::Identity()
            : toEigen(
                  tf_buffer_->lookupTransform(map_frame_, req.pose.header.frame_id, ::ros::Time(0))
                      .transform);
    res.id = pipeline_->addTrack(req.class_name, T_map_frame * toEigen(req.pose.pose),
                                 req.pose.header.stamp.toSec());
    res.success = true;
  } catch (const std::exception& e) {
    res.success = false, res.message = e.what();
  }
  return true;
}

bool TrackerNodelet::onRemoveTrack(scene_graph_tracker::RemoveTrack::Request& req,
                                   scene_graph_tracker::RemoveTrack::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  res.success = pipeline_->removeTrack(req.id);
  if (!res.success) res.message = "no track '" + req.id + "'";
  return true;
}

}  // namespace sgt::ros

PLUGINLIB_EXPORT_CLASS(sgt::ros::TrackerNodelet, nodelet::Nodelet)
