#include "scene_graph_tracker/simulation/building_map.hpp"

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/relations/furniture.hpp"

namespace sgt::sim {

relations::Entity workbenchEntity(const Building& building, const std::string& name) {
  constexpr double kSlab = 0.04;
  relations::Entity e;
  e.name = name;
  e.movable = false;
  e.box.T_world_box.translation() =
      building.workbench_top_centre.cast<double>() - Eigen::Vector3d(0, 0, kSlab / 2);
  e.box.half_extents =
      Eigen::Vector3d(building.workbench_size.x() / 2, building.workbench_size.y() / 2, kSlab / 2);
  return e;
}

void writeBuildingMap(const Building& building, const std::string& mesh_path,
                      const std::string& furniture_path) {
  savePly(building.mesh, mesh_path);
  relations::saveFurniture({workbenchEntity(building)}, furniture_path);
}

}  // namespace sgt::sim
