// Procedural meshes: the generated building has the paper's map size, the object stand-ins have
// the real objects' extents and (when asked) triangle counts, primitives are closed and outward.
#include <gtest/gtest.h>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/procedural_objects.hpp"

namespace sgt {
namespace {

double signedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].cast<double>().dot(
             m.vertices[t[1]].cast<double>().cross(m.vertices[t[2]].cast<double>())) /
         6.0;
  return v;
}

TEST(ProceduralMeshes, BuildingHasThePaperTriangleCount) {
  const Building b = makeBuilding();
  EXPECT_NEAR(static_cast<double>(b.mesh.triangleCount()), 411698.0, 0.02 * 411698.0);
  EXPECT_NO_THROW(validateMesh(b.mesh, "building"));
  const auto box = b.mesh.boundingBox();
  EXPECT_NEAR(box.sizes().x() * box.sizes().y(), 3000.0, 1.0);  // paper: 2,986.6 m^2
  EXPECT_NEAR(b.workbench_top_centre.z(), 0.75f, 1e-4f);
  EXPECT_EQ(b.rooms.size(), 24u);
}

TEST(ProceduralMeshes, ObjectsHaveTheRealExtentsAndCounts) {
  for (const auto& name : paperObjectClasses()) {
    const TriangleMesh m = makeObjectModel(name);
    EXPECT_NO_THROW(validateMesh(m, name));
    EXPECT_TRUE(m.boundingBox().sizes().isApprox(paperObjectExtents(name), 1e-3f)) << name;
    EXPECT_LT(m.boundingBox().center().norm(), 1e-5f) << name;
    const TriangleMesh dense = makeObjectModel(name, paperTriangleCount(name));
    EXPECT_NEAR(static_cast<double>(dense.triangleCount()), paperTriangleCount(name), 2.0) << name;
  }
  EXPECT_THROW(makeObjectModel("hammer"), std::invalid_argument);
}

TEST(ProceduralMeshes, PrimitivesAreClosedAndOutward) {
  EXPECT_NEAR(signedVolume(makeBox({1, 2, 3}, 3)), 6.0, 1e-5);
  EXPECT_NEAR(signedVolume(makeCylinder(0.5f, 2.0f, 256)), M_PI * 0.25 * 2.0, 1e-3);
  EXPECT_NEAR(signedVolume(makeSphere(1.0f, 256, 128)), 4.0 / 3.0 * M_PI, 2e-3);
  TriangleMesh box = makeBox({1, 1, 1});
  subdivideToAtLeast(box, 1000);
  EXPECT_GE(box.triangleCount(), 1000u);
  EXPECT_NEAR(signedVolume(box), 1.0, 1e-5);
}

}  // namespace
}  // namespace sgt
