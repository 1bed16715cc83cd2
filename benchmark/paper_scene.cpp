#include "paper_scene.hpp"

#include <filesystem>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/simulation/procedural_objects.hpp"

namespace sgt::bench {
namespace {

std::string pbrMeshDir() {
  const char* env = std::getenv("SGT_PBR_OBJECTS");
  const std::filesystem::path dir =
      env ? std::filesystem::path(env)
          : std::filesystem::path(SGT_SOURCE_DIR) / ".." / "shared" / "data" / "pbr_objects";
  return std::filesystem::is_directory(dir / "meshes") ? (dir / "meshes").string() : "";
}

std::shared_ptr<TriangleMesh> objectMesh(const std::string& cls, const std::string& pbr_dir) {
  if (!pbr_dir.empty()) {
    const std::string file = cls == "klt" ? "klt3147.stl" : cls + ".stl";
    return std::make_shared<TriangleMesh>(loadMesh(pbr_dir + "/" + cls + "/" + file));
  }
  return std::make_shared<TriangleMesh>(makeObjectModel(cls, paperTriangleCount(cls)));
}

Eigen::Isometry3d pose(const Eigen::Vector3d& t, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(t);
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

}  // namespace

PaperScene makePaperScene(int extra_instances) {
  static const Building building = makeBuilding();
  PaperScene s;
  s.building = building;
  s.map = std::make_shared<TriangleMesh>(building.mesh);
  const std::string pbr = pbrMeshDir();
  s.real_meshes = !pbr.empty();
  s.scene = std::make_unique<RaycastScene>();
  s.scene->setStaticMap(s.map, 1);

  // Objects in a row along the bench (x), resting on its top, turned a little.
  const Eigen::Vector3d top = building.workbench_top_centre.cast<double>();
  const auto& classes = paperObjectClasses();
  const double xs[5] = {-0.45, -0.2, 0.02, 0.3, 0.55};
  const double yaws[5] = {0.3, -0.5, 0.1, 0.2, -0.2};
  NodeId next = 10;
  for (std::size_t k = 0; k < classes.size(); ++k) {
    auto mesh = objectMesh(classes[k], pbr);
    const MeshId id = s.scene->addMesh(mesh);
    const double half_z = 0.5 * mesh->boundingBox().sizes().z() - mesh->boundingBox().center().z();
    const Eigen::Isometry3d T = pose(top + Eigen::Vector3d(xs[k], 0.0, half_z + 0.001), yaws[k]);
    s.scene->addInstance(next, id, T);
    s.objects.push_back({classes[k], next++, id, T});
    s.object_meshes.push_back(std::move(mesh));
  }
  // Extra instances on a grid over the building, skipping the workbench's room.
  const Eigen::AlignedBox3f& bench_room = building.rooms.front();
  int placed = 0;
  for (float y = 1.0f; placed < extra_instances && y < 49.0f; y += 0.35f)
    for (float x = 1.0f; placed < extra_instances && x < 59.0f; x += 0.35f) {
      if (bench_room.contains(Eigen::Vector3f(x, y, 1.0f))) continue;
      const MeshId mesh = s.objects[placed % 5].mesh;
      s.scene->addInstance(next++, mesh,
                           pose(Eigen::Vector3d(x, y, 0.2 + 0.3 * (placed % 7)), 0.1 * placed));
      ++placed;
    }

  s.scene->commit();
  // Robot 1.1 m in front (+y) of the bench, facing it; the head camera looks at the bench centre.
  s.T_world_base = pose(Eigen::Vector3d(top.x(), top.y() + 1.1, 0.0), -M_PI / 2);
  s.T_world_camera = opticalLookAt(s.T_world_base * Eigen::Vector3d(0.1, 0.0, 1.25), top);
  Eigen::Isometry3d T_base_lidar = Eigen::Isometry3d::Identity();
  T_base_lidar.translation() = Eigen::Vector3d(0.0, 0.0, 0.9);
  s.T_world_lidar = s.T_world_base * T_base_lidar;
  s.camera = PinholeModel::xtion();
  s.camera_rays = makeRays(s.camera);
  s.lidar_rays = makeRays(SpinningLidarModel::vlp16());
  return s;
}

std::string meshLabel(const PaperScene& s) {
  return s.real_meshes ? "pbr_objects meshes" : "stand-in meshes";
}

}  // namespace sgt::bench
