#include "scene_graph_tracker/ros/detector_nodelet.hpp"

#include <cv_bridge/cv_bridge.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>

#include <boost/bind/bind.hpp>
#include <cstdio>
#include <pluginlib/class_list_macros.hpp>

#include "scene_graph_tracker/detection/debug_drawing.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/diagnostics.hpp"
#include "scene_graph_tracker/ros/parameters.hpp"

namespace sgt::ros {

void DetectorNodelet::onInit() {
  ::ros::NodeHandle& nh = getNodeHandle();
  ::ros::NodeHandle& pnh = getPrivateNodeHandle();
  // Every parameter of the schema (pipeline/parameter_schema.hpp) by its name; the others keep
  // the option structs' defaults. A bad value stops the nodelet (the loader does not say why).
  params::DetectorParameters p;
  std::vector<std::string> unknown;
  try {
    unknown = readParameters(pnh, params::detectorSchema(), p);
  } catch (const params::ParameterError& e) {
    NODELET_FATAL("detector: %s", e.what());
    throw;
  }
  for (const std::string& name : unknown)
    NODELET_WARN("detector: ~%s is no parameter of the detector (ignored; see doc/parameters.md)",
                 name.c_str());
  const std::string& model = p.model;
  const std::string& catalog_path = p.catalog;
  const std::string& mesh_dir = p.mesh_dir;
  const detection::DecodeOptions& decode = p.decode;
  const detection::PnpOptions& pnp = p.pnp;
  try {
    const ObjectCatalog catalog = loadObjectCatalog(catalog_path, mesh_dir);
    detector_ = std::make_unique<detection::PoseDetector>(model, catalog, decode, pnp, p.inference);
  } catch (const std::exception& e) {
    // Without a model there is nothing to do; say so loudly once and stay up (the rest of the
    // manager keeps running, the tracker can still use other hypothesis sources).
    NODELET_ERROR("detector: disabled: %s", e.what());
    return;
  }
  if (!detector_->keypoints().inferenceNote().empty())
    NODELET_WARN("detector: %s", detector_->keypoints().inferenceNote().c_str());
  const auto& info = detector_->keypoints().info();
  NODELET_INFO("detector: %s (%dx%d input, %zu classes), score >= %.2f, DNN %s / %s",
               info.onnx_path.c_str(), info.input_width, info.input_height, info.names.size(),
               decode.score_threshold, p.inference.backend.c_str(), p.inference.target.c_str());
  hypotheses_pub_ = pnh.advertise<scene_graph_tracker::PoseHypothesisArray>("pose_hypotheses", 5);
  schedule_ = detection::DetectionSchedule(p.schedule);
  tracks_sub_ = nh.subscribe("tracked_objects", 2, &DetectorNodelet::onTracks, this);
  debug_pub_ = pnh.advertise<sensor_msgs::Image>("debug_image", 1);
  pairing_ =
      std::make_unique<DepthPairing>(p.depth_max_offset, p.use_depth ? p.depth_max_wait : 0.0);
  const auto on_error = [this](const std::string& text) { onUndecodable(text); };
  if (p.use_depth) {
    depth_sub_.subscribe(nh, "depth", 3, p.depth_transport, on_error);
    depth_sub_.registerCallback(&DetectorNodelet::onDepth, this);
    NODELET_INFO("detector: depth images: %s", depth_sub_.description().c_str());
    if (p.depth_max_wait > 0.0)
      pairing_timer_ = nh.createWallTimer(::ros::WallDuration(p.depth_max_wait / 2),
                                          [this](const ::ros::WallTimerEvent&) {
                                            if (auto f = pairing_->expired(::ros::WallTime::now()))
                                              detect(*f);
                                          });
  }
  image_sub_.subscribe(nh, "image", 2, p.image_transport, on_error);
  NODELET_INFO("detector: RGB images: %s", image_sub_.description().c_str());
  info_sub_.subscribe(nh, "camera_info", 2);
  sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(SyncPolicy(5), image_sub_,
                                                                      info_sub_);
  sync_->registerCallback(boost::bind(&DetectorNodelet::onImage, this, boost::placeholders::_1,
                                      boost::placeholders::_2));
  diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5);
  diagnostics_timer_ = nh.createWallTimer(
      ::ros::WallDuration(1.0), [this](const ::ros::WallTimerEvent&) { publishDiagnostics(); });
}

// Every image is published (with its hypotheses, perhaps none) or skipped with a reason.
void DetectorNodelet::publishDiagnostics() {
  Counts c;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    c = counts_;
  }
  const bool ok = c.skipped == 0 && c.depth_unused == 0;
  diagnostics_pub_.publish(diagnostics(
      "detector", getName(), ok,
      c.last_problem.empty() ? "detecting" : "detecting; last problem: " + c.last_problem,
      {{"images_in", c.images_in},
       {"images_published", c.published},
       {"images_skipped", c.skipped},
       {"depth_unused", c.depth_unused},
       {"images_waited_for_depth", double(pairing_->waited())},
       {"hypotheses", c.hypotheses},
       {"images_not_scheduled", c.not_scheduled},
       // What never reached the detection: superseded in a full input buffer (node behind),
       // lost before the node (header.seq gaps); depth images only with use_depth.
       {"images_received", double(image_sub_.received())},
       {"images_superseded", double(image_sub_.superseded())},
       {"images_lost_before", double(image_sub_.lost())},
       {"depth_received", double(depth_sub_.received())},
       {"depth_superseded", double(depth_sub_.superseded())},
       {"depth_lost_before", double(depth_sub_.lost())}}));
}

void DetectorNodelet::warn(const std::string& text) {
  if (warnings_.shouldLog(text)) NODELET_WARN("detector: %s", text.c_str());
}

// An image that does not decode is counted as skipped (its RGB or depth image never arrives).
void DetectorNodelet::onUndecodable(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.skipped;
  counts_.last_problem = text;
  warn(text);
}

void DetectorNodelet::onDepth(const sensor_msgs::ImageConstPtr& depth) {
  if (auto frame = pairing_->addDepth(depth, ::ros::WallTime::now())) detect(*frame);
}

std::unique_ptr<RangeMeasurements> DetectorNodelet::registeredDepth(const ::ros::Time& stamp,
                                                                    const PinholeModel& camera) {
  if (!depth_sub_.subscribed()) return nullptr;
  const sensor_msgs::ImageConstPtr best = pairing_->closest(stamp);
  if (!best) {
    char within[32];
    std::snprintf(within, sizeof within, "%.3g s", pairing_->maxOffset());
    warn("no depth image on '" + depth_sub_.topic() + "' within " + within +
         " of the RGB image: distances from PnP alone (set use_depth false if there is no "
         "registered depth)");
    ++counts_.depth_unused;
    return nullptr;
  }
  try {  // registered: the depth image has the RGB camera's size and intrinsics
    return std::make_unique<RangeMeasurements>(fromDepthImage(camera, depth_rays_.rays(camera),
                                                              depthFromImage(*best, camera),
                                                              Eigen::Isometry3d::Identity()));
  } catch (const std::exception& e) {
    ++counts_.depth_unused;
    warn(std::string("depth image not used (it must be registered to the RGB image): ") + e.what());
    return nullptr;
  }
}

void DetectorNodelet::onTracks(const scene_graph_tracker::TrackedObjectArray::ConstPtr& msg) {
  std::vector<detection::ScheduledTrack> tracks;
  for (const auto& t : msg->objects) tracks.push_back({t.id, fromStateCode(t.state)});
  std::lock_guard<std::mutex> lock(mutex_);
  schedule_.observe(msg->header.stamp.toSec(), tracks);
}

bool DetectorNodelet::scheduled(const std_msgs::Header& header, const cv::Mat& rgb) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (schedule_.due(header.stamp.toSec(), rgb)) return true;
    ++counts_.not_scheduled;
  }
  scene_graph_tracker::PoseHypothesisArray none;
  none.header = header;
  hypotheses_pub_.publish(none);
  return false;
}

cv::Mat DetectorNodelet::viewOf(const sensor_msgs::Image& image,
                                const sensor_msgs::CameraInfo& info) const {
  if (!schedule_.watchesView()) return {};  // the options, set once in onInit
  try {
    return rgbFromImage(image, toPinhole(info));
  } catch (const std::exception&) {
    return {};  // detect() reports what is wrong with the image
  }
}

void DetectorNodelet::onImage(const sensor_msgs::ImageConstPtr& image,
                              const sensor_msgs::CameraInfoConstPtr& info) {
  if (!scheduled(image->header, viewOf(*image, *info))) return;
  for (const RgbFrame& frame : pairing_->addImage({image, info}, ::ros::WallTime::now()))
    detect(frame);
}

void DetectorNodelet::detect(const RgbFrame& frame) {
  const sensor_msgs::ImageConstPtr& image = frame.image;
  const sensor_msgs::CameraInfoConstPtr& info = frame.info;
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.images_in;
  std::vector<detection::ObjectDetection> detections;
  cv::Mat rgb;
  try {
    const PinholeModel cam = toPinhole(*info);
    rgb = rgbFromImage(*image, cam);
    const std::unique_ptr<RangeMeasurements> depth = registeredDepth(image->header.stamp, cam);
    detections = detector_->detect(rgb, cam, depth.get());
  } catch (const std::exception& e) {
    ++counts_.skipped;
    counts_.last_problem = std::string("image skipped: ") + e.what();
    warn(counts_.last_problem);
    return;
  }
  scene_graph_tracker::PoseHypothesisArray out;
  out.header = image->header;
  for (const auto& d : detections) {
    if (!d.pnp.ok()) continue;
    scene_graph_tracker::PoseHypothesis h;
    h.class_name = d.detection.class_name;
    h.pose = toPose(d.pnp.T_camera_object);
    h.score = d.detection.score;
    h.up_to_box_half_turns = true;  // cuboid keypoints (detection/keypoint_labels.hpp)
    out.hypotheses.push_back(h);
  }
  hypotheses_pub_.publish(out);
  ++counts_.published, counts_.hypotheses += out.hypotheses.size();
  if (debug_pub_.getNumSubscribers() > 0) {
    detection::drawDetections(rgb, detections, detector_->pnpOptions().min_visibility);
    debug_pub_.publish(cv_bridge::CvImage(image->header, "rgb8", rgb).toImageMsg());
  }
}

}  // namespace sgt::ros

PLUGINLIB_EXPORT_CLASS(sgt::ros::DetectorNodelet, nodelet::Nodelet)
