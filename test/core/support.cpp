#include "support.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace sgt::test {

std::string tempDir() {
  static const std::string dir = [] {
    std::string tmpl = (fs::temp_directory_path() / "sgt_test_XXXXXX").string();
    const char* made = mkdtemp(tmpl.data());
    if (!made) throw std::runtime_error("cannot create a temporary directory");
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(tempDir(), ec);
    });
    return std::string(made);
  }();
  return dir;
}

std::string writeFile(const std::string& name, const std::string& text) {
  const fs::path p = fs::path(tempDir()) / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p.string();
}

std::optional<std::string> pbrObjectsDir() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("SGT_PBR_OBJECTS")) candidates.emplace_back(env);
  candidates.push_back(fs::path(SGT_SOURCE_DIR) / ".." / "shared" / "data" / "pbr_objects");
  for (const auto& c : candidates)
    if (fs::is_directory(c / "meshes")) return fs::canonical(c).string();
  return std::nullopt;
}

double rotationErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

Eigen::Isometry3d poseXyzYaw(const Eigen::Vector3d& t, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

const Building& coarseBuilding() {
  static const Building building = [] {
    BuildingOptions o;
    o.target_triangles = 0;
    o.tile_size = 1.0f;
    return makeBuilding(o);
  }();
  return building;
}

}  // namespace sgt::test
