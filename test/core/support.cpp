#include "support.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <tuple>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

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

StandingView standingView(double distance) {
  StandingView v;
  v.bench = benchScene();
  v.rays = std::make_shared<SensorRays>(makeRays(v.cam));
  std::tie(v.T_map_base, v.T_camera) = facingTheBench(*v.bench, distance);
  v.scan = simulate(*v.bench->world, *v.rays, v.T_camera);
  return v;
}

PipelineFrame depthFrame(int f, const Eigen::Isometry3d& T_map_base, const PinholeModel& cam,
                         const std::shared_ptr<SensorRays>& rays, const SimulatedScan& scan,
                         const Eigen::Isometry3d& T_camera, double sigma, unsigned seed) {
  PipelineFrame frame;
  frame.stamp = f / 30.0;
  frame.T_odom_base = T_map_base;
  frame.measurements.push_back(fromDepthImage(cam, rays, depthImage(scan, *rays), T_camera));
  addDepthNoise(frame.measurements.back(), sigma, seed);
  return frame;
}

const ObjectCatalog& packageCatalog() {
  static const ObjectCatalog c =
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml");
  return c;
}

std::unique_ptr<RaycastScene> objectOnTable(const ObjectClass& object, NodeId node,
                                            const Eigen::Isometry3d& T_world_object) {
  auto scene = std::make_unique<RaycastScene>();
  TriangleMesh table = makeBox({1.6f, 0.8f, 0.04f});
  table.transform(Eigen::Isometry3f(Eigen::Translation3f(0, 0, 0.73f)));
  scene->setStaticMap(std::make_shared<TriangleMesh>(table), 1);
  scene->addInstance(node, scene->addMesh(object.mesh), T_world_object);
  scene->commit();
  return scene;
}

RangeMeasurements xtionView(const RaycastScene& scene, const Eigen::Vector3d& eye,
                            const Eigen::Vector3d& target, double sigma_at_1m, unsigned seed) {
  const PinholeModel camera = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(camera));
  const Eigen::Isometry3d T_world_camera = opticalLookAt(eye, target);
  RangeMeasurements m = fromDepthImage(
      camera, rays, depthImage(simulate(scene, *rays, T_world_camera), *rays), T_world_camera);
  addDepthNoise(m, sigma_at_1m, seed);
  return m;
}

}  // namespace sgt::test
