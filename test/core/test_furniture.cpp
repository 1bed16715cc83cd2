// Furniture files (relations/furniture.hpp): named boxes read back exactly, errors that name the
// problem.
#include <gtest/gtest.h>

#include <cstring>

#include "scene_graph_tracker/relations/furniture.hpp"
#include "support.hpp"

namespace sgt {
namespace {

bool sameBits(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

TEST(Furniture, RotatedBoxesRoundTrip) {
  relations::Entity a;
  a.name = "shelf";
  a.movable = false;
  a.box.T_world_box.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.1, 0.2, 1).normalized()).toRotationMatrix();
  a.box.T_world_box.translation() = Eigen::Vector3d(1.0 / 3.0, -2.7, 0.1);
  a.box.half_extents = Eigen::Vector3d(0.4, 0.15, 1.0 / 7.0);
  relations::Entity b = a;
  b.name = "table two";
  b.box.T_world_box = Eigen::Isometry3d::Identity();
  const std::string path = test::tempDir() + "/two.yaml";
  relations::saveFurniture({a, b}, path);
  const auto back = relations::loadFurniture(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].name, "shelf");
  EXPECT_EQ(back[1].name, "table two");
  EXPECT_TRUE(back[0].box.T_world_box.isApprox(a.box.T_world_box, 1e-15));
  EXPECT_TRUE(sameBits(back[1].box.T_world_box, b.box.T_world_box));
  EXPECT_EQ(back[0].box.half_extents, a.box.half_extents);
}

TEST(Furniture, OrientationIsOptionalAndEmptyListsAreFine) {
  const auto one = relations::loadFurniture(test::writeFile(
      "one.yaml",
      "furniture:\n  - {name: bench, position: [1, 2, 0.7], size: [1.6, 0.8, 0.04]}\n"));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_TRUE(one[0].box.T_world_box.linear().isIdentity(0.0));
  EXPECT_EQ(one[0].box.half_extents, Eigen::Vector3d(0.8, 0.4, 0.02));
  EXPECT_TRUE(relations::loadFurniture(test::writeFile("none.yaml", "furniture: []\n")).empty());
}

TEST(Furniture, BadFilesNameTheProblem) {
  auto fails = [](const std::string& name, const std::string& text, const std::string& what) {
    try {
      relations::loadFurniture(test::writeFile(name, text));
      ADD_FAILURE() << name << ": no error";
    } catch (const relations::FurnitureError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  fails("nolist.yaml", "tables: []\n", "needs a list");
  fails("nosize.yaml", "furniture: [{name: a, position: [0, 0, 0]}]\n", "missing 'size'");
  fails("unknown.yaml",
        "furniture: [{name: a, position: [0, 0, 0], size: [1, 1, 1], colour: red}]\n",
        "unknown key 'colour'");
  fails("twice.yaml",
        "furniture: [{name: a, position: [0, 0, 0], size: [1, 1, 1]}, {name: a, position: [1, 0, "
        "0], size: [1, 1, 1]}]\n",
        "used twice");
  fails("short.yaml", "furniture: [{name: a, position: [0, 0], size: [1, 1, 1]}]\n",
        "expected 3 numbers");
  fails("flat.yaml", "furniture: [{name: a, position: [0, 0, 0], size: [1, 0, 1]}]\n",
        "must be positive");
  fails("nan.yaml", "furniture: [{name: a, position: [0, x, 0], size: [1, 1, 1]}]\n",
        "expected a number");
  EXPECT_THROW(relations::loadFurniture("/nonexistent/furniture.yaml"), relations::FurnitureError);
}

}  // namespace
}  // namespace sgt
