// Simulated measurements: what a sensor at a pose sees of the scene, in the sensor frame.
#pragma once

#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt {

struct SimulatedScan {
  int width = 0, height = 0;
  std::vector<float> range;              // +inf where nothing was hit
  std::vector<Eigen::Vector3f> points;   // sensor frame (NaN where nothing was hit)
  std::vector<Eigen::Vector3f> normals;  // sensor frame, unit, facing the sensor
  std::vector<NodeId> node;              // kNoNode where nothing was hit
};

SimulatedScan simulate(const RaycastScene& scene, const SensorRays& rays,
                       const Eigen::Isometry3d& T_world_sensor);

// Depth image (z along the optical axis, metres, row-major; NaN where nothing was hit) of a
// pinhole simulation.
std::vector<float> depthImage(const SimulatedScan& scan, const SensorRays& rays);

}  // namespace sgt
