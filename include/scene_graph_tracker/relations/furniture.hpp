// Furniture of the static map: named boxes that relations refer to ("relay_1 on workbench"), read
// from a small YAML file beside the map mesh (the tracker's `furniture` parameter, `evaluate
// --furniture`). The format, one entry per piece, poses in the map frame:
//
//   furniture:
//     - name: workbench                       # unique, what relations call it
//       position: [3.0, 2.0, 0.73]            # box centre (m)
//       orientation: [0.0, 0.0, 0.0, 1.0]     # quaternion x, y, z, w; optional, default identity
//       size: [1.6, 0.8, 0.04]                # edge lengths along the box's own axes (m)
//
// Unknown keys are errors. Numbers are written with 17 significant digits, so a saved box reads
// back bit for bit.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scene_graph_tracker/relations/scene_relations.hpp"

namespace sgt::relations {

class FurnitureError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The pieces as relation entities (movable false, no scene node). Throws FurnitureError naming
// the file, the entry and the problem.
std::vector<Entity> loadFurniture(const std::string& path);

// Writes `furniture` (each entity's name and box) in the format above. Throws FurnitureError when
// the file cannot be written.
void saveFurniture(const std::vector<Entity>& furniture, const std::string& path);

}  // namespace sgt::relations
