// Loading meshes through assimp (STL, OBJ, PLY, DAE, glTF, ...) with validation.
#pragma once

#include <stdexcept>
#include <string>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

// Thrown for any mesh that cannot be used; the message names the file and the problem.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MeshLoadOptions {
  // Multiplies every vertex (e.g. 0.001 for meshes stored in millimetres).
  float scale = 1.0f;
  // Degenerate triangles (zero area, repeated index) are dropped with a count in `dropped`
  // when true; when false, any such triangle makes the load fail.
  bool drop_degenerate = true;
  // Largest plausible extent in metres after scaling; larger meshes are rejected as a likely
  // unit mistake (a part exported in millimetres). 0 disables the check.
  float max_extent_m = 0.0f;
};

struct MeshLoadReport {
  std::size_t dropped_degenerate = 0;
  std::size_t merged_meshes = 0;
  std::size_t triangulated_polygons = 0;  // faces of more than three corners, split by the loader
};

TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options = {},
                      MeshLoadReport* report = nullptr);

// Checks a mesh in memory: non-empty, finite vertices, indices in range, no degenerate
// triangles. Throws MeshError naming `what` (a file name or a description).
void validateMesh(const TriangleMesh& mesh, const std::string& what);

// Removes degenerate triangles (repeated index or zero area); returns how many were removed.
std::size_t removeDegenerateTriangles(TriangleMesh& mesh, float min_area = 1e-12f);

// Writes binary STL (used by tools to export generated meshes).
void saveStl(const TriangleMesh& mesh, const std::string& path);
// Writes binary little-endian PLY with the shared vertices and the triangles in their order, so
// loadMesh reads back the same mesh, bit for bit (e.g. a generated static map).
void savePly(const TriangleMesh& mesh, const std::string& path);

// Resolves "package://PKG/x" and "file://x" URIs and relative paths (relative to `base_dir`).
// PKG through findPackageDir (util/package_files.hpp): scene_graph_tracker's share directory,
// other packages in ROS_PACKAGE_PATH. Throws MeshError when the package is not found.
std::string resolveResourcePath(const std::string& uri, const std::string& base_dir = "");

}  // namespace sgt
