// Helpers shared by the core tests: temporary files, the optional paper meshes.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::test {

// A fresh directory under /tmp, removed at the end of the test program.
std::string tempDir();
// Writes `text` to tempDir()/name and returns the path.
std::string writeFile(const std::string& name, const std::string& text);

// ../shared/data/pbr_objects (or $SGT_PBR_OBJECTS) when present.
std::optional<std::string> pbrObjectsDir();
#define SGT_REQUIRE_PBR_OBJECTS(var)                                                 \
  const auto var##_opt = ::sgt::test::pbrObjectsDir();                               \
  if (!var##_opt) GTEST_SKIP() << "../shared/data/pbr_objects not present: skipped"; \
  const std::string var = *var##_opt

// Translation t, then yaw about z.
Eigen::Isometry3d poseXyzYaw(const Eigen::Vector3d& t, double yaw = 0.0);

// The generated building with a coarse tessellation (1 m quads; same rooms, furniture and
// workbench as the benchmarks' 411k-triangle one), built once per test program.
const Building& coarseBuilding();

// The workbench of the coarse building with the five catalog classes along it (multimeter,
// screwdriver, materialbox, klt, relay; object nodes 10..14) resting on its top, committed in a
// ray-casting scene that also holds the static map (node 1). `robot` stands 1.1 m in front of the
// bench facing it; `T_base_camera` looks at the bench top from 1.25 m height.
struct BenchScene {
  std::shared_ptr<TriangleMesh> map;
  std::shared_ptr<ObjectCatalog> catalog;
  std::unique_ptr<RaycastScene> world;
  Eigen::Vector3d top;  // centre of the bench top
  std::vector<std::string> classes;
  std::vector<Eigen::Isometry3d> truth;  // T_map_object per class
  Eigen::Isometry3d T_map_base, T_base_camera, T_base_lidar;
  static NodeId objectNode(std::size_t k) { return static_cast<NodeId>(10 + k); }
};
std::unique_ptr<BenchScene> benchScene();

// The robot `distance` m in front of the bench, facing it, and its camera (1.25 m high) looking
// at the bench top: T_map_base, T_map_camera.
std::pair<Eigen::Isometry3d, Eigen::Isometry3d> facingTheBench(const BenchScene& bench,
                                                               double distance);

// A QVGA depth image (the Xtion at 320 x 240): a quarter of the rays on an object.
PinholeModel qvgaCam();

// Angle of the rotation between two orientations, degrees.
double rotationErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

// The bench as the camera of a robot standing `distance` m in front of it sees it (one scan).
struct StandingView {
  std::unique_ptr<BenchScene> bench;
  PinholeModel cam = PinholeModel::xtion();
  std::shared_ptr<SensorRays> rays;
  Eigen::Isometry3d T_map_base, T_camera;
  SimulatedScan scan;
};
StandingView standingView(double distance);

// Frame f (30 Hz) from a robot standing at T_map_base: the scan's depth image, with depth noise
// of `sigma` at 1 m.
PipelineFrame depthFrame(int f, const Eigen::Isometry3d& T_map_base, const PinholeModel& cam,
                         const std::shared_ptr<SensorRays>& rays, const SimulatedScan& scan,
                         const Eigen::Isometry3d& T_camera, double sigma, unsigned seed);

// The package's catalog (config/objects.yaml), loaded once per test program.
const ObjectCatalog& packageCatalog();

// A 1.6 x 0.8 m table top (static map, node 1; top at z 0.75) with `object` at `T_world_object`
// (node `node`), committed.
std::unique_ptr<RaycastScene> objectOnTable(const ObjectClass& object, NodeId node,
                                            const Eigen::Isometry3d& T_world_object);
// The Xtion's depth image of `scene` from `eye` looking at `target`, with structured-light noise
// of sigma_at_1m (seed `seed`).
RangeMeasurements xtionView(const RaycastScene& scene, const Eigen::Vector3d& eye,
                            const Eigen::Vector3d& target, double sigma_at_1m, unsigned seed);

}  // namespace sgt::test
