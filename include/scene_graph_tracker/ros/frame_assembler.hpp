// One frame from stamped sensor messages, for the live nodelet and the bag reader alike.
//
// A frame is built for each depth image (with its CameraInfo). It gets:
// - the odometry: odom -> base at the image's stamp, and odom -> sensor at each sensor's stamp;
// - the LiDAR: the newest cloud not later than the image, used once (older ones are dropped);
//   likewise the newest planar laser scan (sensor_msgs/LaserScan), for localization;
// - the pose hypotheses: the one array closest in time to the image within hypothesis_max_age (a
//   detector emits one array per image; using every array in the window would count each object
//   several times), moved into the base frame at the image's stamp (through the odometry at the
//   array's own stamp when it is another: the robot moved in between); arrays up to the image's
//   stamp are then dropped.
//   (The nodelet holds an image until its own array came: ros/hypothesis_wait.hpp.)
// The camera's ray model comes from its CameraInfo. A cloud organized as the configured LiDAR grid
// (options) uses that grid's rays; any other cloud, and a laser scan, one ray per return
// (conversions.hpp).
#pragma once

#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {

struct FrameAssemblerOptions {
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  double hypothesis_max_age = 0.1;  // s
  SpinningLidarModel lidar = SpinningLidarModel::vlp16();
  std::size_t max_buffered_clouds = 5, max_buffered_hypotheses = 30;
};

// The options from the tracker's node parameters (frames, hypothesis_max_age, lidar/*); throws
// std::invalid_argument when they describe no LiDAR.
FrameAssemblerOptions assemblerOptions(const params::TrackerNodeOptions& node);

struct AssembledFrame {
  PipelineFrame frame;
  sensor_msgs::PointCloud2::ConstPtr cloud;  // the scan in the frame, if any
  std::vector<std::string> warnings;         // parts left out, and why
};

class FrameAssembler {
 public:
  // T_target_source at a stamp; throws (e.g. tf2::TransformException) when it is not known.
  using Lookup = std::function<Eigen::Isometry3d(
      const std::string& target, const std::string& source, const ::ros::Time& stamp)>;
  FrameAssembler(FrameAssemblerOptions options, Lookup lookup);

  const FrameAssemblerOptions& options() const { return options_; }
  Eigen::Isometry3d lookup(const std::string& target, const std::string& source,
                           const ::ros::Time& stamp) const {
    return lookup_(target, source, stamp);
  }
  void addCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud);
  void addLaserScan(const sensor_msgs::LaserScan::ConstPtr& scan);
  void addHypotheses(const scene_graph_tracker::PoseHypothesisArray::ConstPtr& hypotheses);
  void clear();  // forget the buffered scans and hypotheses (time went back)
  // The frame of a depth image. Throws when the image cannot be used (no frame then); a scan that
  // cannot be used is left out with a warning.
  AssembledFrame assemble(const sensor_msgs::Image& depth, const sensor_msgs::CameraInfo& info);

 private:
  void addDepth(AssembledFrame& out, const sensor_msgs::Image& depth,
                const sensor_msgs::CameraInfo& info);
  void addHypothesesOf(AssembledFrame& out, const sensor_msgs::Image& depth);
  Eigen::Isometry3d baseFromHypotheses(const AssembledFrame& out, const sensor_msgs::Image& depth,
                                       const std_msgs::Header& of) const;
  void addScan(AssembledFrame& out, const ::ros::Time& stamp);
  void addLaserScan(AssembledFrame& out, const ::ros::Time& stamp);

  FrameAssemblerOptions options_;
  Lookup lookup_;
  PinholeRayCache camera_rays_;
  std::shared_ptr<const SensorRays> lidar_rays_;
  std::deque<sensor_msgs::PointCloud2::ConstPtr> clouds_;
  std::deque<sensor_msgs::LaserScan::ConstPtr> laser_scans_;
  std::deque<scene_graph_tracker::PoseHypothesisArray::ConstPtr> hypotheses_;
};

}  // namespace sgt::ros
