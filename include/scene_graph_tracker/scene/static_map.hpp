// The static map (the building, furniture): one triangle mesh in the map frame, from a URDF
// (visual meshes, boxes, cylinders, spheres with their origins, joints at zero) or a mesh file.
#pragma once

#include <string>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

// Dispatches on the extension: .urdf → staticMapFromUrdf, anything else → loadMesh.
TriangleMesh loadStaticMap(const std::string& path);
// Throws MeshError naming the file and link for unreadable URDFs or their meshes.
TriangleMesh staticMapFromUrdf(const std::string& urdf_path);

}  // namespace sgt
