// Writes the package's own procedural object models (meshes/<class>.stl), used by
// config/objects.yaml. Usage: generate_meshes [OUTPUT_DIR]   (default: <package>/meshes)
#include <filesystem>
#include <iostream>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/simulation/procedural_objects.hpp"
#include "scene_graph_tracker/util/package_files.hpp"

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : sgt::packageFile("meshes");
  std::filesystem::create_directories(dir);
  for (const auto& name : sgt::paperObjectClasses()) {
    const sgt::TriangleMesh mesh = sgt::makeObjectModel(name);
    const std::string path = dir + "/" + name + ".stl";
    sgt::saveStl(mesh, path);
    const auto size = mesh.boundingBox().sizes();
    std::cout << path << ": " << mesh.triangleCount() << " triangles, " << size.x() << " x "
              << size.y() << " x " << size.z() << " m\n";
  }
  return 0;
}
