#include "scene_graph_tracker/ros/tracker_nodelet.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <boost/bind/bind.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <scene_graph_tracker/SceneGraph.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <optional>

#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/ros/closest_in_time.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/relation_markers.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"

namespace sgt::ros {
namespace {

std_msgs::ColorRGBA colour(TrackState s) {
  std_msgs::ColorRGBA c;
  c.a = 0.85f;
  switch (s) {
    case TrackState::kTentative: c.r = 1.0f, c.g = 0.8f, c.b = 0.1f; break;
    case TrackState::kConfirmed: c.r = 0.1f, c.g = 0.8f, c.b = 0.2f; break;
    default: c.r = c.g = c.b = 0.55f; break;
  }
  return c;
}

std::uint8_t stateCode(TrackState s) {
  return s == TrackState::kTentative ? scene_graph_tracker::TrackedObject::TENTATIVE
         : s == TrackState::kConfirmed ? scene_graph_tracker::TrackedObject::CONFIRMED
                                       : scene_graph_tracker::TrackedObject::LOST;
}

}  // namespace

void TrackerNodelet::onInit() {
  ::ros::NodeHandle& nh = getNodeHandle();
  ::ros::NodeHandle& pnh = getPrivateNodeHandle();
  map_frame_ = pnh.param<std::string>("map_frame", "map");
  odom_frame_ = pnh.param<std::string>("odom_frame", "odom");
  base_frame_ = pnh.param<std::string>("base_frame", "base_link");
  publish_map_odom_ = pnh.param("publish_map_odom", true);
  publish_object_tf_ = pnh.param("publish_object_tf", false);
  hypothesis_max_age_ = pnh.param("hypothesis_max_age", 0.1);

  PipelineOptions o;
  o.refiner.rounds = pnh.param("refine/rounds", o.refiner.rounds);
  o.refiner.steps = pnh.param("refine/steps", o.refiner.steps);
  o.refiner.max_dist_first = static_cast<float>(pnh.param("refine/max_dist_first", double(o.refiner.max_dist_first)));
  o.refiner.max_dist_last = static_cast<float>(pnh.param("refine/max_dist_last", double(o.refiner.max_dist_last)));
  o.localize = pnh.param("localize", o.localize);
  o.association_distance = pnh.param("association_distance", o.association_distance);
  o.remove_after_s = pnh.param("remove_after", o.remove_after_s);
  o.min_fit_support = pnh.param("min_fit_support", o.min_fit_support);
  o.min_weak_fit_inliers = pnh.param("min_weak_fit_inliers", o.min_weak_fit_inliers);
  o.max_sunk_fraction = pnh.param("max_sunk_fraction", o.max_sunk_fraction);
  o.min_hypothesis_score = pnh.param("min_hypothesis_score", o.min_hypothesis_score);
  o.run_presegmentation = pnh.param("presegment", o.run_presegmentation);
  o.search_orientations = pnh.param("search_orientations", o.search_orientations);
  o.research_below_fit_support = pnh.param("research_below_fit_support", o.research_below_fit_support);
  o.contest_restarts = pnh.param("contest_restarts", o.contest_restarts);
  o.compute_relations = pnh.param("relations/enabled", o.compute_relations);
  o.reparent = pnh.param("relations/reparent", o.reparent);
  o.relation_options.directional = pnh.param("relations/directional", o.relation_options.directional);
  o.relation_options.camera_relative = pnh.param("relations/camera_relative", o.relation_options.camera_relative);
  if (pnh.param("relations/relaxed", false)) o.relation_options.directional_mode = relations::Mode::Relaxed;
  o.relation_hysteresis.appear_frames = pnh.param("relations/appear_frames", o.relation_hysteresis.appear_frames);
  o.relation_hysteresis.disappear_frames = pnh.param("relations/disappear_frames", o.relation_hysteresis.disappear_frames);

  const std::string catalog_path = pnh.param<std::string>("catalog", std::string(SGT_SOURCE_DIR) + "/config/objects.yaml");
  const std::string mesh_dir = pnh.param<std::string>("mesh_dir", "");
  // The static world: a mesh or URDF, and optionally its furniture (relations/furniture.hpp); for
  // the simulated building, tools/write_map writes both.
  const std::string map_path = pnh.param<std::string>("static_map", "");
  const std::string furniture_path = pnh.param<std::string>("furniture", "");
  if (map_path.empty()) {
    NODELET_FATAL("tracker: ~static_map is required (a mesh file or a URDF of the static world)");
    throw std::runtime_error("tracker: ~static_map is not set");
  }
  auto catalog = std::make_shared<ObjectCatalog>(loadObjectCatalog(catalog_path, mesh_dir));
  auto map = std::make_shared<TriangleMesh>(loadStaticMap(map_path));
  pipeline_ = std::make_unique<FramePipeline>(catalog, map, o);
  if (!furniture_path.empty()) pipeline_->setFurniture(relations::loadFurniture(furniture_path));
  NODELET_INFO("tracker: %zu classes from %s, static map %s (%zu triangles), %zu pieces of furniture", catalog->size(),
               catalog_path.c_str(), map_path.c_str(), map->triangleCount(), pipeline_->furniture().size());

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>(::ros::Duration(30.0));
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  objects_pub_ = pnh.advertise<scene_graph_tracker::TrackedObjectArray>("tracked_objects", 5);
  graph_pub_ = pnh.advertise<scene_graph_tracker::SceneGraph>("scene_graph", 5);
  unassigned_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("unassigned_points", 2);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 2);
  diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5);
  depth_sub_.subscribe(nh, "depth/image", 3);
  info_sub_.subscribe(nh, "depth/camera_info", 3);
  sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(SyncPolicy(5), depth_sub_, info_sub_);
  sync_->registerCallback(boost::bind(&TrackerNodelet::onDepth, this, boost::placeholders::_1, boost::placeholders::_2));
  cloud_sub_ = nh.subscribe("points", 2, &TrackerNodelet::onCloud, this);
  hypotheses_sub_ = nh.subscribe("pose_hypotheses", 10, &TrackerNodelet::onHypotheses, this);
  // Run-time parameters start from the values loaded above (config/tracker.yaml).
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<scene_graph_tracker::TrackerConfig>>(reconfigure_mutex_, pnh);
  scene_graph_tracker::TrackerConfig initial;
  initial.refine_rounds = o.refiner.rounds, initial.refine_steps = o.refiner.steps;
  initial.max_dist_first = o.refiner.max_dist_first, initial.max_dist_last = o.refiner.max_dist_last;
  initial.association_distance = o.association_distance, initial.remove_after = o.remove_after_s;
  initial.min_hypothesis_score = o.min_hypothesis_score, initial.localize = o.localize;
  initial.presegment = o.run_presegmentation;
  reconfigure_->updateConfig(initial);
  reconfigure_->setCallback(boost::bind(&TrackerNodelet::onReconfigure, this, boost::placeholders::_1,
                                        boost::placeholders::_2));
  reset_srv_ = pnh.advertiseService("reset", &TrackerNodelet::onReset, this);
  add_srv_ = pnh.advertiseService("add_track", &TrackerNodelet::onAddTrack, this);
  remove_srv_ = pnh.advertiseService("remove_track", &TrackerNodelet::onRemoveTrack, this);
}

void TrackerNodelet::warn(const std::string& text) {
  if (warnings_.shouldLog(text)) NODELET_WARN("tracker: %s", text.c_str());
}

void TrackerNodelet::onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  std::lock_guard<std::mutex> lock(mutex_);
  pushRecent(clouds_, cloud, 5);
}

void TrackerNodelet::onHypotheses(const scene_graph_tracker::PoseHypothesisArrayConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  pushRecent(hypotheses_, msg, 30);
}

void TrackerNodelet::onDepth(const sensor_msgs::ImageConstPtr& depth, const sensor_msgs::CameraInfoConstPtr& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ::ros::Time stamp = depth->header.stamp;
  if (!last_stamp_.isZero() && stamp < last_stamp_) {
    NODELET_WARN("tracker: time went back by %.3f s (bag loop or clock reset): tracks reset",
                 (last_stamp_ - stamp).toSec());
    pipeline_->reset();
  }
  last_stamp_ = stamp;
  PipelineFrame frame;
  frame.stamp = stamp.toSec();
  const auto lookup = [&](const std::string& target, const std::string& source, const ::ros::Time& t) {
    return toEigen(tf_buffer_->lookupTransform(target, source, t, ::ros::Duration(0.05)).transform);
  };
  try {
    const PinholeModel cam = toPinhole(*info);
    static thread_local PinholeRayCache ray_cache;
    const auto rays = ray_cache.rays(cam);
    frame.T_odom_base = lookup(odom_frame_, base_frame_, stamp);
    frame.measurements.push_back(fromDepthImage(cam, rays, depthFromImage(*depth, cam),
                                                lookup(odom_frame_, depth->header.frame_id, stamp),
                                                depth->header.frame_id));
    const Eigen::Isometry3d T_base_camera = lookup(base_frame_, depth->header.frame_id, stamp);
    // The detections of this image: the one hypothesis array closest in time (a detector emits one
    // per image); using every array within the window would count each object several times.
    const scene_graph_tracker::PoseHypothesisArrayConstPtr best = closestInTime(hypotheses_, stamp, hypothesis_max_age_);
    if (best) {
      const Eigen::Isometry3d T_base_frame = best->header.frame_id == depth->header.frame_id
                                                 ? T_base_camera
                                                 : lookup(base_frame_, best->header.frame_id, best->header.stamp);
      for (const auto& p : best->hypotheses)
        frame.hypotheses.push_back({p.class_name, T_base_frame * toEigen(p.pose), p.score});
    }
    hypotheses_.erase(std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                                     [&](const auto& h) { return h->header.stamp <= stamp; }),
                      hypotheses_.end());
  } catch (const std::exception& e) {
    warn(std::string("depth frame skipped: ") + e.what());
    publishDiagnostics(std::string("depth frame skipped: ") + e.what(), nullptr);
    return;
  }
  // The newest scan not later than the image, once.
  sensor_msgs::PointCloud2ConstPtr cloud;
  while (!clouds_.empty() && clouds_.front()->header.stamp <= stamp) cloud = clouds_.front(), clouds_.pop_front();
  if (cloud) {
    try {
      static const auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
      const SpinningLidarModel model = SpinningLidarModel::vlp16();
      frame.measurements.push_back(fromRanges(model, lidar_rays, rangesFromCloud(*cloud, model),
                                              lookup(odom_frame_, cloud->header.frame_id, cloud->header.stamp),
                                              cloud->header.frame_id));
    } catch (const std::exception& e) {
      warn(std::string("point cloud skipped: ") + e.what());
    }
  }
  const PipelineResult r = pipeline_->process(std::move(frame));
  publish(r, stamp);
  publishDiagnostics("", &r);
}

void TrackerNodelet::publish(const PipelineResult& r, const ::ros::Time& stamp) {
  scene_graph_tracker::TrackedObjectArray objects;
  objects.header.stamp = stamp;
  objects.header.frame_id = map_frame_;
  scene_graph_tracker::SceneGraph graph;
  graph.header = objects.header;
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  int marker_id = 0;
  std::map<std::string, const TrackedObject*> by_id;
  for (const TrackedObject& o : r.objects) by_id[o.id] = &o;
  for (const relations::Edge& e : r.relations) {
    scene_graph_tracker::SceneGraphEdge edge;
    edge.subject = e.subject, edge.relation = relations::relationName(e.relation), edge.object = e.object;
    graph.edges.push_back(edge);
  }
  for (const TrackedObject& o : r.objects) {
    // In the graph a track in / on another is that track's child (pose relative to it).
    const auto parent = by_id.find(o.parent);
    const bool child = parent != by_id.end();
    scene_graph_tracker::TrackedObject t;
    t.id = o.id, t.class_name = o.class_name, t.state = stateCode(o.state), t.parent = child ? o.parent : map_frame_;
    t.pose.pose = toPose(o.T_map_object);
    for (int i = 0; i < 36; ++i) t.pose.covariance[i] = o.covariance(i / 6, i % 6);
    t.inlier_ratio = static_cast<float>(o.quality.inlier_ratio), t.inliers = o.quality.inliers;
    objects.objects.push_back(t);
    scene_graph_tracker::SceneGraphNode n;
    n.id = o.id, n.class_name = o.class_name, n.parent = t.parent;
    n.T_parent_node = toTransform(child ? Eigen::Isometry3d(parent->second->T_map_object.inverse() * o.T_map_object)
                                        : o.T_map_object);
    graph.nodes.push_back(n);

    const ObjectClass& c = pipeline_->catalog().get(o.class_name);
    visualization_msgs::Marker m;
    m.header = objects.header;
    m.ns = "objects", m.id = marker_id++, m.type = visualization_msgs::Marker::MESH_RESOURCE;
    m.mesh_resource = "file://" + c.mesh_path;
    m.pose = t.pose.pose, m.scale.x = m.scale.y = m.scale.z = 1.0, m.color = colour(o.state);
    markers.markers.push_back(m);
    visualization_msgs::Marker box = m;
    box.ns = "boxes", box.id = marker_id++, box.type = visualization_msgs::Marker::CUBE, box.mesh_resource.clear();
    const Eigen::Vector3d centre = o.T_map_object * c.box.center().cast<double>();
    box.pose.position.x = centre.x(), box.pose.position.y = centre.y(), box.pose.position.z = centre.z();
    box.scale.x = c.box.sizes().x(), box.scale.y = c.box.sizes().y(), box.scale.z = c.box.sizes().z();
    box.color.a = 0.15f;
    markers.markers.push_back(box);
    visualization_msgs::Marker label = m;
    label.ns = "labels", label.id = marker_id++, label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    label.mesh_resource.clear();
    label.text = o.id + " (" + toString(o.state) + ")";
    label.pose.position.z += c.box.sizes().z() * 0.5 + 0.05;
    label.scale.z = 0.04, label.color.r = label.color.g = label.color.b = label.color.a = 1.0f;
    markers.markers.push_back(label);
    if (publish_object_tf_) {
      geometry_msgs::TransformStamped tf;
      tf.header = objects.header, tf.child_frame_id = o.id, tf.transform = toTransform(o.T_map_object);
      tf_broadcaster_->sendTransform(tf);
    }
  }
  // Relation edges: lines between box centres (tracks and furniture) with labels.
  std::map<std::string, Eigen::Vector3d> centres;
  for (const TrackedObject& o : r.objects)
    centres[o.id] = o.T_map_object * pipeline_->catalog().get(o.class_name).box.center().cast<double>();
  for (const relations::Entity& f : pipeline_->furniture()) centres[f.name] = f.box.T_world_box.translation();
  for (auto& m : relationMarkers(r.relations, centres, map_frame_, stamp, marker_id)) markers.markers.push_back(m);
  objects_pub_.publish(objects);
  graph_pub_.publish(graph);
  markers_pub_.publish(markers);
  if (publish_map_odom_) {
    geometry_msgs::TransformStamped tf;
    tf.header.stamp = stamp, tf.header.frame_id = map_frame_, tf.child_frame_id = odom_frame_;
    tf.transform = toTransform(r.T_map_odom);
    tf_broadcaster_->sendTransform(tf);
  }
  if (unassigned_pub_.getNumSubscribers() > 0) {
    sensor_msgs::PointCloud2 cloud;
    cloud.header = objects.header;
    std::size_t n = 0;
    for (const auto& p : r.presegmentation) n += p.unknown_points.size();
    sensor_msgs::PointCloud2Modifier mod(cloud);
    mod.setPointCloud2FieldsByString(1, "xyz");
    mod.resize(n);
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    for (const auto& p : r.presegmentation)
      for (const auto& q : p.unknown_points) *x = q.x(), *y = q.y(), *z = q.z(), ++x, ++y, ++z;
    unassigned_pub_.publish(cloud);
  }
}

void TrackerNodelet::publishDiagnostics(const std::string& problem, const PipelineResult* r) {
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ::ros::Time::now();
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "scene_graph_tracker: tracker", s.hardware_id = getName();
  s.level = problem.empty() ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
  s.message = problem.empty() ? "tracking" : problem;
  const auto kv = [&](const std::string& k, const std::string& v) {
    diagnostic_msgs::KeyValue x;
    x.key = k, x.value = v;
    s.values.push_back(x);
  };
  if (r) {
    kv("objects", std::to_string(r->objects.size()));
    kv("frame_ms", std::to_string(r->times.total_ms));
    kv("localized", r->localized ? "yes" : "no");
  }
  array.status.push_back(s);
  diagnostics_pub_.publish(array);
}

void TrackerNodelet::onReconfigure(scene_graph_tracker::TrackerConfig& c, std::uint32_t) {
  std::lock_guard<std::mutex> lock(mutex_);
  PipelineOptions o = pipeline_->options();
  o.refiner.rounds = c.refine_rounds, o.refiner.steps = c.refine_steps;
  o.refiner.max_dist_first = static_cast<float>(c.max_dist_first);
  o.refiner.max_dist_last = static_cast<float>(c.max_dist_last);
  o.association_distance = c.association_distance, o.remove_after_s = c.remove_after;
  o.min_hypothesis_score = c.min_hypothesis_score, o.localize = c.localize, o.run_presegmentation = c.presegment;
  pipeline_->setOptions(o);
  NODELET_INFO("tracker: reconfigured (%d rounds x %d steps, thresholds %.3f -> %.3f m)", c.refine_rounds,
               c.refine_steps, c.max_dist_first, c.max_dist_last);
}

bool TrackerNodelet::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  pipeline_->reset();
  NODELET_INFO("tracker: reset");
  return true;
}

bool TrackerNodelet::onAddTrack(scene_graph_tracker::AddTrack::Request& req, scene_graph_tracker::AddTrack::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    const Eigen::Isometry3d T_map_frame =
        req.pose.header.frame_id.empty() || req.pose.header.frame_id == map_frame_
            ? Eigen::Isometry3d::Identity()
            : toEigen(tf_buffer_->lookupTransform(map_frame_, req.pose.header.frame_id, ::ros::Time(0)).transform);
    res.id = pipeline_->addTrack(req.class_name, T_map_frame * toEigen(req.pose.pose), req.pose.header.stamp.toSec());
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
