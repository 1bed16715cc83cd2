// The generated building as the tracker's static world: its mesh and its furniture (the
// workbench top), the two files the tracker nodelet takes (`static_map`, `furniture`) and
// `evaluate` too (`--map`, `--furniture`). tools/write_map writes them, so the building itself
// never enters the product path.
#pragma once

#include <string>

#include "scene_graph_tracker/relations/scene_relations.hpp"
#include "scene_graph_tracker/simulation/building.hpp"

namespace sgt::sim {

// The name relations use for the workbench top (static furniture of the map).
inline constexpr const char* kWorkbenchName = "workbench";

// The workbench top as furniture: a 4 cm slab under the top surface.
relations::Entity workbenchEntity(const Building& building,
                                  const std::string& name = kWorkbenchName);

// Writes the building's mesh (PLY, geometry/mesh_io.hpp: read back bit for bit) and its furniture
// (relations/furniture.hpp: the workbench top). Throws on I/O errors.
void writeBuildingMap(const Building& building, const std::string& mesh_path,
                      const std::string& furniture_path);

}  // namespace sgt::sim
