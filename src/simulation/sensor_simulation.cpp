#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

#include <limits>

namespace sgt {

SimulatedScan simulate(const RaycastScene& scene, const SensorRays& rays,
                       const Eigen::Isometry3d& T_world_sensor) {
  RayHits hits;
  scene.cast(rays, T_world_sensor, hits);
  SimulatedScan out;
  out.width = rays.width;
  out.height = rays.height;
  out.range = hits.range;
  out.node = hits.node;
  out.points.resize(rays.size());
  out.normals.resize(rays.size());
  const Eigen::Matrix3f R_sensor_world = T_world_sensor.linear().transpose().cast<float>();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (hits.node[i] == kNoNode) {
      out.points[i].setConstant(nan);
      out.normals[i].setConstant(nan);
      continue;
    }
    const Eigen::Vector3f origin = rays.origins.empty() ? Eigen::Vector3f::Zero() : rays.origins[i];
    out.points[i] = origin + rays.directions[i] * hits.range[i];
    out.normals[i] = R_sensor_world * hits.normal[i];
  }
  return out;
}

std::vector<float> depthImage(const SimulatedScan& scan, const SensorRays& rays) {
  std::vector<float> depth(scan.range.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < depth.size(); ++i)
    if (scan.node[i] != kNoNode) depth[i] = scan.points[i].z();
  return depth;
}

}  // namespace sgt
