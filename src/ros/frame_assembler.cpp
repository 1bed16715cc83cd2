#include "scene_graph_tracker/ros/frame_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scene_graph_tracker/ros/closest_in_time.hpp"

namespace sgt::ros {

FrameAssemblerOptions assemblerOptions(const params::TrackerNodeOptions& node) {
  FrameAssemblerOptions o;
  o.odom_frame = node.odom_frame, o.base_frame = node.base_frame;
  o.hypothesis_max_age = node.hypothesis_max_age;
  o.lidar = node.lidar;
  o.lidar.theta_inc = 2.0 * M_PI / o.lidar.columns;  // one turn over the columns
  if (!(o.lidar.phi_min < o.lidar.phi_max) || !(o.lidar.range_min < o.lidar.range_max))
    throw std::invalid_argument("lidar/* parameters describe no sensor");
  return o;
}

FrameAssembler::FrameAssembler(FrameAssemblerOptions options, Lookup lookup)
    : options_(std::move(options)),
      lookup_(std::move(lookup)),
      lidar_rays_(std::make_shared<SensorRays>(makeRays(options_.lidar))) {}

void FrameAssembler::addCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud) {
  if (cloud) pushRecent(clouds_, cloud, options_.max_buffered_clouds);
}

void FrameAssembler::addLaserScan(const sensor_msgs::LaserScan::ConstPtr& scan) {
  if (scan) pushRecent(laser_scans_, scan, options_.max_buffered_clouds);
}

void FrameAssembler::addHypotheses(
    const scene_graph_tracker::PoseHypothesisArray::ConstPtr& hypotheses) {
  if (hypotheses) pushRecent(hypotheses_, hypotheses, options_.max_buffered_hypotheses);
}

void FrameAssembler::clear() {
  clouds_.clear();
  laser_scans_.clear();
  hypotheses_.clear();
}

AssembledFrame FrameAssembler::assemble(const sensor_msgs::Image& depth,
                                        const sensor_msgs::CameraInfo& info) {
  AssembledFrame out;
  out.frame.stamp = depth.header.stamp.toSec();
  addDepth(out, depth, info);
  addHypothesesOf(out, depth);
  addScan(out, depth.header.stamp);
  addLaserScan(out, depth.header.stamp);
  return out;
}

void FrameAssembler::addDepth(AssembledFrame& out, const sensor_msgs::Image& depth,
                              const sensor_msgs::CameraInfo& info) {
  const PinholeModel cam = toPinhole(info);
  std::vector<float> ranges =
      depthFromImage(depth, cam);  // checks the image against the info first
  const ::ros::Time& stamp = depth.header.stamp;
  out.frame.T_odom_base = lookup_(options_.odom_frame, options_.base_frame, stamp);
  const Eigen::Isometry3d T_odom_camera =
      lookup_(options_.odom_frame, depth.header.frame_id, stamp);
  out.frame.measurements.push_back(fromDepthImage(cam, camera_rays_.rays(cam), std::move(ranges),
                                                  T_odom_camera, depth.header.frame_id));
}

namespace {

// The array's hypotheses into the frame, T_base_frame applied; a bad one costs itself.
void addHypothesisArray(AssembledFrame& out, const Eigen::Isometry3d& T_base_frame,
                        const scene_graph_tracker::PoseHypothesisArray& array) {
  for (const auto& p : array.hypotheses) {
    try {
      if (!std::isfinite(p.score)) throw ConversionError("non-finite score");
      out.frame.hypotheses.push_back(
          {p.class_name, T_base_frame * toEigen(p.pose), p.score, p.up_to_box_half_turns != 0});
    } catch (const ConversionError& e) {
      out.warnings.push_back("hypothesis of class '" + p.class_name + "' dropped: " + e.what());
    }
  }
}

}  // namespace

// base <- the hypotheses' frame, for the base at the image's stamp. The detector saw the objects
// at the array's stamp: an array from another time (a detector slower than the camera, an array
// matched within hypothesis_max_age) goes through the odometry then, as the robot moved between.
Eigen::Isometry3d FrameAssembler::baseFromHypotheses(const AssembledFrame& out,
                                                     const sensor_msgs::Image& depth,
                                                     const std_msgs::Header& of) const {
  if (of.stamp == depth.header.stamp)
    return lookup_(options_.base_frame, of.frame_id, depth.header.stamp);
  return out.frame.T_odom_base.inverse() * lookup_(options_.odom_frame, of.frame_id, of.stamp);
}

void FrameAssembler::addHypothesesOf(AssembledFrame& out, const sensor_msgs::Image& depth) {
  const ::ros::Time& stamp = depth.header.stamp;
  if (const auto best = closestInTime(hypotheses_, stamp, options_.hypothesis_max_age)) {
    try {
      addHypothesisArray(out, baseFromHypotheses(out, depth, best->header), *best);
    } catch (const std::exception& e) {  // no transform for the array: it costs itself
      out.warnings.push_back("hypothesis array in frame '" + best->header.frame_id +
                             "' dropped: " + e.what());
    }
  }
  hypotheses_.erase(std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                                   [&](const auto& h) { return h->header.stamp <= stamp; }),
                    hypotheses_.end());
}

namespace {

// The newest message not later than `stamp`; it and the older ones leave the buffer.
template <typename Ptr>
Ptr takeNewest(std::deque<Ptr>& buffer, const ::ros::Time& stamp) {
  Ptr newest;
  while (!buffer.empty() && buffer.front()->header.stamp <= stamp)
    newest = buffer.front(), buffer.pop_front();
  return newest;
}

}  // namespace

void FrameAssembler::addScan(AssembledFrame& out, const ::ros::Time& stamp) {
  const sensor_msgs::PointCloud2::ConstPtr cloud = takeNewest(clouds_, stamp);
  if (!cloud) return;
  try {
    const ::ros::Time& t = cloud->header.stamp;
    out.frame.measurements.push_back(
        measurementsFromCloud(*cloud, options_.lidar, lidar_rays_,
                              lookup_(options_.odom_frame, cloud->header.frame_id, t)));
    out.cloud = cloud;
  } catch (const std::exception& e) {
    out.warnings.push_back("LiDAR scan at " + std::to_string(cloud->header.stamp.toSec()) +
                           " skipped: " + e.what());
  }
}

void FrameAssembler::addLaserScan(AssembledFrame& out, const ::ros::Time& stamp) {
  const sensor_msgs::LaserScan::ConstPtr scan = takeNewest(laser_scans_, stamp);
  if (!scan) return;
  try {
    const ::ros::Time& t = scan->header.stamp;
    out.frame.measurements.push_back(
        measurementsFromScan(*scan, lookup_(options_.odom_frame, scan->header.frame_id, t)));
  } catch (const std::exception& e) {
    out.warnings.push_back("laser scan at " + std::to_string(scan->header.stamp.toSec()) +
                           " skipped: " + e.what());
  }
}

}  // namespace sgt::ros
