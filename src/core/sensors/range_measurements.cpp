#include "scene_graph_tracker/sensors/range_measurements.hpp"

#include <limits>
#include <stdexcept>

namespace sgt {

std::size_t RangeMeasurements::validCount() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < range.size(); ++i) n += valid(i);
  return n;
}

RangeMeasurements fromDepthImage(const PinholeModel& model, std::shared_ptr<const SensorRays> rays,
                                 const std::vector<float>& depth, const Eigen::Isometry3d& T,
                                 const std::string& sensor) {
  const std::size_t expected = static_cast<std::size_t>(model.width) * model.height;
  if (depth.size() != expected || !rays || rays->size() != expected)
    throw std::invalid_argument(sensor + ": depth image has " + std::to_string(depth.size()) +
                                " pixels, rays " + std::to_string(rays ? rays->size() : 0) +
                                ", camera model " + std::to_string(model.width) + "x" +
                                std::to_string(model.height));
  RangeMeasurements m;
  m.sensor = sensor;
  m.model = model;
  m.T_world_sensor = T;
  m.range.resize(expected);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < expected; ++i) {
    const float z = depth[i];
    m.range[i] = (std::isfinite(z) && z > 0.0f) ? z / rays->directions[i].z() : nan;
  }
  m.rays = std::move(rays);
  return m;
}

RangeMeasurements fromRanges(const SensorModel& model, std::shared_ptr<const SensorRays> rays,
                             std::vector<float> ranges, const Eigen::Isometry3d& T,
                             const std::string& sensor) {
  if (!rays || ranges.size() != rays->size())
    throw std::invalid_argument(sensor + ": " + std::to_string(ranges.size()) + " ranges for " +
                                std::to_string(rays ? rays->size() : 0) + " rays");
  RangeMeasurements m;
  m.sensor = sensor;
  m.model = model;
  m.rays = std::move(rays);
  m.range = std::move(ranges);
  m.T_world_sensor = T;
  return m;
}

}  // namespace sgt
