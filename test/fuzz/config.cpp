// Configuration files through temporary files: the first byte picks the loader, the rest is the
// file. 0: an object catalog (loadObjectCatalog; with a mesh-directory override when the first
// byte is 3), 1: a scenario (loadScenario), 2: a URDF static map (loadStaticMap of a .urdf). The
// file sits beside a small catalog (catalog.yaml: box, cylinder), its meshes (box.stl,
// cylinder.stl), a floor (floor.ply) and a URDF (map.urdf), so relative paths can name them.
// Scenarios with a large generated building are skipped (largeBuilding).
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"

namespace {

// The files beside the fuzzed one, written once.
const std::string& fixtureDir() {
  static const std::string dir = [] {
    const std::string& d = sgt::fuzz::tempDir();
    sgt::saveStl(sgt::makeBox(Eigen::Vector3f(0.2f, 0.15f, 0.1f)), d + "/box.stl");
    sgt::saveStl(sgt::makeCylinder(0.05f, 0.2f, 12), d + "/cylinder.stl");
    sgt::savePly(sgt::makeBox(Eigen::Vector3f(4.0f, 4.0f, 0.02f)), d + "/floor.ply");
    sgt::fuzz::writeTemp("catalog.yaml",
                         "objects:\n"
                         "  box: {mesh: box.stl}\n"
                         "  cylinder:\n"
                         "    mesh: cylinder.stl\n"
                         "    symmetries_continuous: [{axis: [0, 0, 1], offset: [0, 0, 0]}]\n");
    sgt::fuzz::writeTemp("map.urdf",
                         "<robot name=\"map\"><link name=\"floor\"><visual><geometry>"
                         "<box size=\"4 4 0.02\"/></geometry></visual></link></robot>\n");
    return d;
  }();
  return dir;
}

// A scenario whose generated building loadScenario accepts but that is large (more than a
// million triangles, or floor quads up to the loader's limit of 2.5e7): generating it takes
// seconds to minutes under the sanitizers, by design, so such inputs are skipped.
bool largeBuilding(const std::uint8_t* data, std::size_t size) {
  try {
    const YAML::Node b =
        YAML::Load(std::string(reinterpret_cast<const char*>(data), size))["world"]["building"];
    if (!b) return false;
    const auto number = [&](const char* key, double fallback) {
      return b.IsMap() && b[key] && b[key].IsScalar() ? b[key].as<double>() : fallback;
    };
    const double target = number("target_triangles", 411698);
    if (target != 0) return target > 1e6;
    const double tile = number("tile_size", 0.25) > 0 ? number("tile_size", 0.25) : 0.25;
    const double quads =
        std::ceil(number("length_x", 60) / tile) * std::ceil(number("length_y", 50) / tile);
    return quads > 1e6 && quads <= 2.5e7;
  } catch (const YAML::Exception&) {
    return false;  // loadScenario says what is wrong
  }
}

}  // namespace

int sgtFuzzConfig(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string& dir = fixtureDir();
  switch (data[0] % 4) {
    case 0:
    case 3:
      try {
        const sgt::ObjectCatalog catalog = sgt::loadObjectCatalog(
            sgt::fuzz::writeTemp("fuzz.yaml", data + 1, size - 1), data[0] % 4 == 3 ? dir : "");
        for (const std::string& n : catalog.names())
          sgt::fuzz::expect(catalog.get(n).mesh && !catalog.get(n).mesh->empty(),
                            "a mesh for every class");
      } catch (const sgt::CatalogError& e) {
        if (sgt::fuzz::verbose()) std::fprintf(stderr, "%s\n", e.what());
      }
      break;
    case 1: {
      if (largeBuilding(data + 1, size - 1)) break;
      sgt::sim::Scenario s;
      try {
        s = sgt::sim::loadScenario(sgt::fuzz::writeTemp("fuzz.yaml", data + 1, size - 1));
      } catch (const sgt::sim::ScenarioError& e) {
        if (sgt::fuzz::verbose()) std::fprintf(stderr, "%s\n", e.what());
        break;
      }
      sgt::fuzz::expect(s.static_map && s.catalog && !s.robot.empty(),
                        "a complete scenario (map, catalog, robot)");
      try {
        sgt::validateMesh(*s.static_map, "the scenario's static map");
      } catch (const sgt::MeshError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        sgt::fuzz::expect(false, "a scenario with a valid static map");
      }
      break;
    }
    case 2: {
      sgt::TriangleMesh map;
      try {
        map = sgt::loadStaticMap(sgt::fuzz::writeTemp("fuzz.urdf", data + 1, size - 1));
      } catch (const sgt::MeshError& e) {
        if (sgt::fuzz::verbose()) std::fprintf(stderr, "%s\n", e.what());
        break;
      }
      try {
        sgt::validateMesh(map, "the static map");
      } catch (const sgt::MeshError&) {
        sgt::fuzz::expect(false, "loadStaticMap to return a valid mesh");
      }
      break;
    }
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzConfig)
