// Helpers shared by the core tests: temporary files, the optional paper meshes.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <optional>
#include <string>

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

// Angle of the rotation between two orientations, degrees.
double rotationErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace sgt::test
