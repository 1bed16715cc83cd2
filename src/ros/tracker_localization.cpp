// The tracker nodelet's localization modes: its own (ray-cast against the static map, map -> odom
// published while converged, seeded by initialpose) or an external one (map -> odom from TF at
// each frame's stamp, e.g. amcl; nothing published).
#include <cmath>
#include <stdexcept>

#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/tracker_nodelet.hpp"

namespace sgt::ros {

void TrackerNodelet::setUpLocalization(const params::TrackerNodeOptions& node,
                                       PipelineOptions& options) {
  if (node.localization != "own" && node.localization != "external")
    throw params::ParameterError("tracker: ~localization is '" + node.localization +
                                 "': expected own or external");
  external_localization_ = node.localization == "external";
  publish_map_odom_ = node.publish_map_odom && !external_localization_;
  if (external_localization_) {
    options.localize = false;
    if (node.publish_map_odom)
      NODELET_INFO("tracker: external localization: %s -> %s comes from TF, not published here",
                   map_frame_.c_str(), odom_frame_.c_str());
  }
  ::ros::NodeHandle& nh = getNodeHandle();
  initialpose_sub_ = nh.subscribe("initialpose", 1, &TrackerNodelet::onInitialPose, this);
}

// The robot's pose in the map (rviz "2D Pose Estimate"): map -> odom from it and the latest
// odom -> base. The own localization refines from there. The tracks are removed: their map poses
// were measured with the pose this one corrects.
void TrackerNodelet::onInitialPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (external_localization_) {
    ++counts_.warnings;
    warn("initialpose ignored: the localization is external");
    return;
  }
  try {
    if (msg->header.frame_id != map_frame_)
      throw std::invalid_argument("its frame is '" + msg->header.frame_id + "', not " + map_frame_);
    const Eigen::Isometry3d T_map_base = toEigen(msg->pose.pose);
    const Eigen::Isometry3d T_odom_base =
        toEigen(tf_buffer_->lookupTransform(odom_frame_, base_frame_, ::ros::Time(0)).transform);
    pipeline_->reset();
    pipeline_->setMapOdom(T_map_base * T_odom_base.inverse());
    const Eigen::Vector3d t = T_map_base.translation();
    const double yaw = std::atan2(T_map_base.linear()(1, 0), T_map_base.linear()(0, 0));
    NODELET_INFO("tracker: pose set from initialpose (tracks reset): x %.3f y %.3f yaw %.1f deg",
                 t.x(), t.y(), yaw * 180.0 / M_PI);
  } catch (const std::exception& e) {
    ++counts_.warnings;
    warn(std::string("initialpose ignored: ") + e.what());
  }
}

// map -> odom from TF at the frame's stamp; without one the last stays (warned, counted).
void TrackerNodelet::applyExternalLocalization(const ::ros::Time& stamp) {
  try {
    pipeline_->setMapOdom(
        toEigen(tf_buffer_->lookupTransform(map_frame_, odom_frame_, stamp).transform));
    external_pose_ok_ = true;
  } catch (const std::exception& e) {
    external_pose_ok_ = false;
    ++counts_.warnings;
    warn("external localization: no " + map_frame_ + " -> " + odom_frame_ +
         " for the frame (the last one is kept): " + e.what());
  }
}

}  // namespace sgt::ros
