// Conversions between ROS messages and core types. Every function that reads a message checks
// it and throws ConversionError with a message that names the problem (wrong encoding, size
// mismatch, missing fields), so nodes can warn and keep running.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <vector>

#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt::ros {

struct ConversionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Eigen::Isometry3d toEigen(const geometry_msgs::Pose& p);
Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t);
geometry_msgs::Pose toPose(const Eigen::Isometry3d& T);
geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);

// Pinhole model from camera_info (K; distortion is ignored: use rectified images).
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

// A VLP-16 style cloud (fields x, y, z; optional intensity, ring) as ranges along the model's
// rays. An organized cloud of the model's size keeps its order (rows = rings); any other cloud is
// binned into the model's ring x column grid by each point's elevation and azimuth (the nearest
// return wins). Throws when x/y/z are missing or not float32.
std::vector<float> rangesFromCloud(const sensor_msgs::PointCloud2& cloud,
                                   const SpinningLidarModel& model);
// Organized rings x columns cloud with fields x, y, z, intensity (float32) and ring (uint16); NaN
// points where there is no return.
sensor_msgs::PointCloud2 cloudFromRanges(const std::vector<float>& ranges, const SensorRays& rays,
                                         const std::vector<float>& intensity);

}  // namespace sgt::ros
