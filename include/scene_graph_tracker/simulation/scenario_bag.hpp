// Writes a simulated scenario into a rosbag: the interface between `simulate` and everything that
// reads bags (the evaluator, rosbag play). Topics, frames and their meaning:
//
//   /tf_static  (tf2_msgs/TFMessage, once at the start, latched)  base_link ->
//   camera_rgb_optical_frame,
//                base_link -> velodyne
//   /tf         (per sensor stamp)  odom -> base_link: the drifting wheel odometry (starts at the
//   true
//                start pose). No map -> odom: a localizer (the tracker) publishes that.
//   /simulated/map_odom_prior (geometry_msgs/TransformStamped, once, latched) map -> odom: the
//                identity up to the configured initial error (noise.odometry.initial_error, in the
//                robot's start frame). map -> odom -> base_link through it is the odometry PRIOR,
//                where odometry alone thinks the robot is. The TRUE pose is
//                /ground_truth/base_pose.
//   /camera/rgb/image_raw (rgb8), /camera/rgb/camera_info
//   /camera/depth_registered/image_raw (32FC1 m, NaN = no return; same frame and intrinsics as
//   RGB), /camera/depth_registered/camera_info /velodyne_points (PointCloud2, organized 16 x 1824:
//   x, y, z, intensity, ring; frame velodyne) /ground_truth/objects (ObjectPoseArray, frame map,
//   per camera frame; catalog objects only) /ground_truth/base_pose (PoseStamped, frame map, per
//   sensor stamp: camera and LiDAR stamps, once each) /ground_truth/depth_labels (mono8, like the
//   depth image), /ground_truth/velodyne_labels (mono8, 16 x 1824):
//                0 no return, 1 static map, 2 catalog object, 3 distractor
//   /simulated/pose_hypotheses (PoseHypothesisArray, frame camera_rgb_optical_frame, stamp of the
//   image)
// Every message's bag time equals its header stamp (/tf_static: the first stamp).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "scene_graph_tracker/simulation/scenario.hpp"

namespace sgt::ros {

namespace topics {
inline constexpr const char* kTf = "/tf";
inline constexpr const char* kTfStatic = "/tf_static";
inline constexpr const char* kRgb = "/camera/rgb/image_raw";
inline constexpr const char* kRgbInfo = "/camera/rgb/camera_info";
inline constexpr const char* kDepth = "/camera/depth_registered/image_raw";
inline constexpr const char* kDepthInfo = "/camera/depth_registered/camera_info";
inline constexpr const char* kVelodyne = "/velodyne_points";
inline constexpr const char* kGtObjects = "/ground_truth/objects";
inline constexpr const char* kGtBasePose = "/ground_truth/base_pose";
inline constexpr const char* kGtDepthLabels = "/ground_truth/depth_labels";
inline constexpr const char* kGtVelodyneLabels = "/ground_truth/velodyne_labels";
inline constexpr const char* kHypotheses = "/simulated/pose_hypotheses";
inline constexpr const char* kMapOdomPrior = "/simulated/map_odom_prior";
}  // namespace topics

namespace frames {
inline constexpr const char* kMap = "map";
inline constexpr const char* kOdom = "odom";
inline constexpr const char* kBase = "base_link";
inline constexpr const char* kCamera = "camera_rgb_optical_frame";
inline constexpr const char* kLidar = "velodyne";
}  // namespace frames

struct ScenarioBagOptions {
  bool lz4 = false;  // compress chunks with LZ4 (smaller, a little slower to write)
};

struct ScenarioBagSummary {
  std::size_t camera_frames = 0;
  std::size_t lidar_scans = 0;
  std::size_t stamps = 0;  // distinct sensor stamps (= /tf and /ground_truth/base_pose messages)
  std::size_t hypotheses = 0;
};

// Called after each sensor stamp with (stamps done, stamps in total).
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

// Simulates `scenario` and writes the bag at `path` (overwritten). Throws on I/O errors.
ScenarioBagSummary writeScenarioBag(const sim::Scenario& scenario, const std::string& path,
                                    const ProgressCallback& progress = {},
                                    const ScenarioBagOptions& options = {});

}  // namespace sgt::ros
