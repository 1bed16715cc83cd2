// Conversions between ROS messages and core types. Every function that reads a message checks
// it and throws ConversionError with a message that names the problem (wrong encoding, size
// mismatch, missing fields), so nodes can warn and keep running.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <vector>

#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/tracking/track_lifecycle.hpp"

namespace sgt::ros {

struct ConversionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Eigen::Isometry3d toEigen(const geometry_msgs::Pose& p);
Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t);
geometry_msgs::Pose toPose(const Eigen::Isometry3d& T);
geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
// TrackedObject.state codes (TENTATIVE, CONFIRMED, LOST; a removed track is never published) and
// back; an unknown code reads as tentative.
std::uint8_t toStateCode(TrackState s);
TrackState fromStateCode(std::uint8_t code);

// Pinhole model from camera_info: K, and D when it is plumb_bob (its rays then come from the
// distorted model); another distortion model with non-zero D throws (rectify the images).
PinholeModel toPinhole(const sensor_msgs::CameraInfo& info, float range_min = 0.2f,
                       float range_max = 10.0f);
sensor_msgs::CameraInfo toCameraInfo(const PinholeModel& cam);

// Depth image (32FC1 metres or 16UC1 millimetres, 0 = no return) as metres, NaN for no return.
// Throws on another encoding or when its size differs from the camera model's.
std::vector<float> depthFromImage(const sensor_msgs::Image& img, const PinholeModel& cam);
// Colour image (rgb8, bgr8, rgba8, bgra8 or mono8) as an 8-bit 3-channel RGB matrix (a copy).
// Throws on another encoding, an empty image, or a size that differs from the camera model's.
cv::Mat rgbFromImage(const sensor_msgs::Image& img, const PinholeModel& cam);
sensor_msgs::Image depthToImage(const std::vector<float>& depth_m, int width, int height);  // 32FC1

// A range sensor's cloud (fields x, y, z, all float32 or all float64, in the cloud's frame, whose
// origin is the sensor's; any byte order, point and row stride) as measurements along rays:
// - a cloud organized as the configured `grid` (height = rings, width = columns, like the
//   simulator's VLP-16) keeps its order on `grid_rays` (the grid's rays), NaN where no return;
// - any other cloud (unorganized, a ring field, another scanner's rings: VLP-32C, Ouster, Hesai,
//   Livox, Luminar) gets one ray per point with a finite, non-zero position, from the origin
//   (model PointRays), with the grid's range limits.
// Throws ConversionError on a malformed cloud.
RangeMeasurements measurementsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                        const SpinningLidarModel& grid,
                                        std::shared_ptr<const SensorRays> grid_rays,
                                        const Eigen::Isometry3d& T_world_sensor);
bool matchesGrid(const sensor_msgs::PointCloud2& cloud, const SpinningLidarModel& grid);
// A planar laser scan (a Tiago's base laser on /scan) as one ray per beam in the scan's frame
// (x forward, angles counter-clockwise about z); a range outside [range_min, range_max] or not
// finite is no return. Throws ConversionError on a scan with no usable angles or limits.
RangeMeasurements measurementsFromScan(const sensor_msgs::LaserScan& scan,
                                       const Eigen::Isometry3d& T_world_sensor);
// Organized rings x columns cloud with fields x, y, z, intensity (float32) and ring (uint16); NaN
// points where there is no return.
sensor_msgs::PointCloud2 cloudFromRanges(const std::vector<float>& ranges, const SensorRays& rays,
                                         const std::vector<float>& intensity);

}  // namespace sgt::ros
