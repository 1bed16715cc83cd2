// Mesh loading through assimp (sgt::loadMesh): the bytes after the first two as a file whose
// extension the first byte picks (.ply, .obj, .stl, .off); the second byte picks the load
// options (scale, dropping degenerate triangles, the extent limit).
#include <cmath>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"

int sgtFuzzMesh(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  static const char* const kExtensions[] = {".ply", ".obj", ".stl", ".off"};
  const std::string path =
      sgt::fuzz::writeTemp(std::string("mesh") + kExtensions[data[0] % 4], data + 2, size - 2);
  sgt::MeshLoadOptions options;
  const std::uint8_t o = data[1];
  static const float kScales[] = {1.0f, 0.001f, 1000.0f, 0.0f, -1.0f, NAN, INFINITY, 1e-30f};
  options.scale = kScales[o & 7];
  options.drop_degenerate = !(o & 8);
  options.max_extent_m = (o & 16) ? 5.0f : 0.0f;
  sgt::TriangleMesh mesh;
  try {
    mesh = sgt::loadMesh(path, options);
  } catch (const sgt::MeshError&) {
    return 0;
  }
  try {
    sgt::validateMesh(mesh, path);
  } catch (const sgt::MeshError&) {
    sgt::fuzz::expect(false, "loadMesh to return a valid mesh");
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzMesh)
