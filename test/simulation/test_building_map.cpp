// The generated building as map files (write_map): the mesh and the workbench furniture read back
// bit for bit, so the tracker and `evaluate --map FILE --furniture FILE` see exactly the building
// and the furniture `evaluate --map building` builds in memory. (The furniture format itself:
// test/core/test_furniture.cpp.)
#include <gtest/gtest.h>

#include <cstring>

#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"
#include "scene_graph_tracker/simulation/building_map.hpp"
#include "support.hpp"

namespace sgt {
namespace {

template <typename T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool sameBits(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

TEST(BuildingMap, WorkbenchEntityIsTheSlabUnderTheTop) {
  const Building& b = test::coarseBuilding();
  const relations::Entity e = sim::workbenchEntity(b);
  EXPECT_EQ(e.name, "workbench");
  EXPECT_EQ(e.node, kNoNode);
  EXPECT_FALSE(e.movable);
  EXPECT_TRUE(e.box.T_world_box.linear().isIdentity(0.0));
  EXPECT_EQ(e.box.T_world_box.translation(),
            b.workbench_top_centre.cast<double>() - Eigen::Vector3d(0, 0, 0.02));
  EXPECT_EQ(e.box.half_extents,
            Eigen::Vector3d(b.workbench_size.x() / 2.0, b.workbench_size.y() / 2.0, 0.02));
}

TEST(BuildingMap, FilesReadBackBitForBit) {
  const Building& b = test::coarseBuilding();
  const std::string dir = test::tempDir();
  sim::writeBuildingMap(b, dir + "/building.ply", dir + "/furniture.yaml");

  const TriangleMesh mesh = loadStaticMap(dir + "/building.ply");
  ASSERT_EQ(mesh.vertices.size(), b.mesh.vertices.size());
  ASSERT_EQ(mesh.triangles.size(), b.mesh.triangles.size());
  EXPECT_EQ(std::memcmp(mesh.vertices.data(), b.mesh.vertices.data(),
                        sizeof(Eigen::Vector3f) * mesh.vertices.size()),
            0);
  EXPECT_EQ(mesh.triangles, b.mesh.triangles);

  const std::vector<relations::Entity> furniture =
      relations::loadFurniture(dir + "/furniture.yaml");
  ASSERT_EQ(furniture.size(), 1u);
  const relations::Entity expected = sim::workbenchEntity(b);
  EXPECT_EQ(furniture[0].name, expected.name);
  EXPECT_EQ(furniture[0].node, expected.node);
  EXPECT_EQ(furniture[0].movable, expected.movable);
  EXPECT_EQ(furniture[0].kind, expected.kind);
  EXPECT_TRUE(sameBits(furniture[0].box.T_world_box, expected.box.T_world_box));
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(sameBits(furniture[0].box.half_extents[i], expected.box.half_extents[i]));
}

}  // namespace
}  // namespace sgt
