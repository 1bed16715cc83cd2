#include "support.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace sgt::test {

std::string tempDir() {
  // Removed by its destructor at exit (an atexit handler registered while the static was being
  // initialised would run after the static's destructor, reading a freed string).
  struct Dir {
    std::string path;
    Dir() {
      std::string tmpl = (fs::temp_directory_path() / "sgt_test_XXXXXX").string();
      const char* made = mkdtemp(tmpl.data());
      if (!made) throw std::runtime_error("cannot create a temporary directory");
      path = made;
    }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
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

std::unique_ptr<BenchScene> benchScene() {
  auto b = std::make_unique<BenchScene>();
  const Building& building = coarseBuilding();
  b->map = std::make_shared<TriangleMesh>(building.mesh);
  b->catalog = std::make_shared<ObjectCatalog>(
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml"));
  b->world = std::make_unique<RaycastScene>();
  b->world->setStaticMap(b->map, 1);
  b->top = building.workbench_top_centre.cast<double>();
  b->classes = {"multimeter", "screwdriver", "materialbox", "klt", "relay"};
  const double xs[5] = {-0.45, -0.2, 0.02, 0.3, 0.55}, yaws[5] = {0.3, -0.5, 0.1, 0.2, -0.2};
  for (std::size_t k = 0; k < b->classes.size(); ++k) {
    const ObjectClass& c = b->catalog->get(b->classes[k]);
    const double half_z = 0.5 * c.box.sizes().z() - c.box.center().z();
    b->truth.push_back(poseXyzYaw(b->top + Eigen::Vector3d(xs[k], 0.0, half_z + 0.001), yaws[k]));
    b->world->addInstance(BenchScene::objectNode(k), b->world->addMesh(c.mesh), b->truth.back());
  }
  b->world->commit();
  b->T_map_base = poseXyzYaw(Eigen::Vector3d(b->top.x(), b->top.y() + 1.1, 0.0), -M_PI / 2);
  b->T_base_camera = b->T_map_base.inverse() *
                     opticalLookAt(b->T_map_base * Eigen::Vector3d(0.1, 0, 1.25), b->top);
  b->T_base_lidar = poseXyzYaw(Eigen::Vector3d(0, 0, 0.9), 0.0);
  return b;
}

std::pair<Eigen::Isometry3d, Eigen::Isometry3d> facingTheBench(const BenchScene& bench,
                                                               double distance) {
  const Eigen::Isometry3d T_map_base =
      poseXyzYaw(bench.top + Eigen::Vector3d(0.0, distance, -bench.top.z()), -M_PI / 2);
  return {T_map_base, opticalLookAt(T_map_base * Eigen::Vector3d(0.1, 0, 1.25), bench.top)};
}

PinholeModel qvgaCam() {
  PinholeModel cam = PinholeModel::xtion();
  cam.width = 320, cam.height = 240, cam.fx = cam.fy = 262.5, cam.cx = 159.5, cam.cy = 119.5;
  return cam;
}

}  // namespace sgt::test
