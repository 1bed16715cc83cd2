// Helpers shared by the core tests: temporary files, the optional paper meshes.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "scene_graph_tracker/geometry/building.hpp"

namespace sgt::test {

// A fresh directory under /tmp, removed at the end of the test program.
std::string tempDir();
// Writes `text` to tempDir()/name and returns the path.
std::string writeFile(const std::string& name, const std::string& text);

// ../shared/data/pbr_objects (or $SGT_PBR_OBJECTS) when present.
std::optional<std::string> pbrObjectsDir();
#define SGT_REQUIRE_PBR_OBJECTS(var)                                                  \
  const auto var##_opt = ::sgt::test::pbrObjectsDir();                               \
  if (!var##_opt) GTEST_SKIP() << "../shared/data/pbr_objects not present: skipped"; \
  const std::string var = *var##_opt

// Translation t, then yaw about z.
Eigen::Isometry3d poseXyzYaw(const Eigen::Vector3d& t, double yaw = 0.0);

// The generated building with a coarse tessellation (1 m quads; same rooms, furniture and
// workbench as the benchmarks' 411k-triangle one), built once per test program.
const Building& coarseBuilding();

// Angle of the rotation between two orientations, degrees.
double rotationErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace sgt::test
