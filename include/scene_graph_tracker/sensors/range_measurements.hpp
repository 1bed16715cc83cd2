// One sensor's measured ranges for one frame, with the rays they were measured along and the
// sensor pose in the map frame. Depth images and LiDAR scans both become this.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt {

// A range sensor's returns as one ray per return, from the sensor origin, with no grid to search:
// an unorganized cloud or one of a LiDAR other than the configured grid (VLP-32C, Ouster, Hesai,
// Livox, Luminar), or a 2D laser scan.
struct PointRays {};

using SensorModel = std::variant<std::monostate, PinholeModel, SpinningLidarModel, PointRays>;

struct RangeMeasurements {
  std::string sensor;  // a name for messages (e.g. the frame id)
  SensorModel model;   // when known, lets consumers find the rays near an object quickly
  std::shared_ptr<const SensorRays> rays;
  std::vector<float> range;  // per ray, metres along the unit ray; not finite or <= 0: no return
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();

  std::size_t size() const { return range.size(); }
  bool valid(std::size_t i) const {
    const float r = range[i];
    return std::isfinite(r) && r >= rays->range_min && r <= rays->range_max;
  }
  std::size_t validCount() const;
  Eigen::Vector3f pointInSensor(std::size_t i) const { return rays->directions[i] * range[i]; }
  bool isDepthImage() const { return std::holds_alternative<PinholeModel>(model); }
};

// From a depth image (z along the optical axis, metres, row-major, NaN/0 for no return).
// Throws std::invalid_argument when the image size does not match the model.
RangeMeasurements fromDepthImage(const PinholeModel& model, std::shared_ptr<const SensorRays> rays,
                                 const std::vector<float>& depth_m,
                                 const Eigen::Isometry3d& T_world_sensor,
                                 const std::string& sensor = "camera");

// From ranges ordered like the model's rays (LiDAR scan as a range image).
RangeMeasurements fromRanges(const SensorModel& model, std::shared_ptr<const SensorRays> rays,
                             std::vector<float> ranges, const Eigen::Isometry3d& T_world_sensor,
                             const std::string& sensor = "lidar");

}  // namespace sgt
