// Writes a simulated static world as the files the tracker takes: the mesh (PLY) for the nodelet's
// `static_map` parameter and `evaluate --map`, the furniture (YAML, format:
// include/scene_graph_tracker/relations/furniture.hpp) for `furniture` and `evaluate --furniture`.
//
//   rosrun scene_graph_tracker write_map --mesh OUT.ply --furniture OUT.yaml [--scenario FILE.yaml]
//
// Without --scenario: the generated building with its default options (what `evaluate --map
// building` builds). With it: the scenario's world, a generated building with the scenario's
// options (mesh and workbench top) or its mesh / URDF world (mesh only, no furniture).
#include <iostream>

#include "command_line.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/simulation/building_map.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"

int main(int argc, char** argv) {
  using namespace sgt;
  const cli::Flags flags("write_map", "--mesh OUT.ply --furniture OUT.yaml [--scenario FILE.yaml]");
  std::string mesh_path, furniture_path, scenario_path;
  flags.parse(
      argc, argv,
      {{"--mesh", &mesh_path}, {"--furniture", &furniture_path}, {"--scenario", &scenario_path}});
  if (mesh_path.empty() || furniture_path.empty())
    flags.fail("--mesh and --furniture are required");
  try {
    BuildingOptions building_options;
    if (!scenario_path.empty()) {
      const sim::Scenario scenario = sim::loadScenario(scenario_path);
      if (scenario.world.kind != sim::WorldSpec::Kind::Building) {
        savePly(*scenario.static_map, mesh_path);
        relations::saveFurniture({}, furniture_path);
        std::cout << mesh_path << ": " << scenario.static_map->triangleCount() << " triangles ("
                  << scenario.world.path << "); " << furniture_path << ": no furniture\n";
        return 0;
      }
      building_options = scenario.world.building;
    }
    const Building building = makeBuilding(building_options);
    sim::writeBuildingMap(building, mesh_path, furniture_path);
    std::cout << mesh_path << ": the generated building, " << building.mesh.triangleCount()
              << " triangles; " << furniture_path << ": its workbench top (" << sim::kWorkbenchName
              << ")\n";
  } catch (const std::exception& e) {
    std::cerr << "write_map: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
