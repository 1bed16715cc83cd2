// Scene graph: world transforms, moves, removal and re-parenting that keeps world poses.
#include <gtest/gtest.h>

#include "scene_graph_tracker/scene/scene_graph.hpp"

namespace sgt {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(x, y, z));
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

TEST(SceneGraph, WorldTransformsCompose) {
  SceneGraph g;
  const NodeId table = g.add("table", "", kWorldNode, pose(2, 0, 0.75, M_PI / 2));
  const NodeId klt = g.add("klt_1", "klt", table, pose(0.5, 0, 0.07, 0));
  const Eigen::Isometry3d T = g.worldTransform(klt);
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(2, 0.5, 0.82), 1e-12));
  EXPECT_EQ(g.node(klt).parent, table);
  EXPECT_EQ(g.find("klt_1"), klt);
  EXPECT_EQ(g.find("nothing"), kNoNode);
  EXPECT_EQ(g.subtree(table), (std::vector<NodeId>{table, klt}));
}

TEST(SceneGraph, MovingAParentMovesItsChildren) {
  SceneGraph g;
  const NodeId klt = g.add("klt_1", "klt", kWorldNode, pose(1, 1, 0.8, 0));
  const NodeId relay = g.add("relay_1", "relay", klt, pose(0.05, 0, 0.0, 0.3));
  g.setWorldTransform(klt, pose(3, 1, 0.8, M_PI));
  const Eigen::Isometry3d T = g.worldTransform(relay);
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(2.95, 1, 0.8), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(T.linear()).angle(), M_PI - 0.3, 1e-9);
}

TEST(SceneGraph, ReparentKeepsWorldPose) {
  SceneGraph g;
  const NodeId cupboard = g.add("cupboard", "", kWorldNode, pose(4, -2, 0, 1.1));
  const NodeId cup = g.add("cup", "cup", kWorldNode, pose(4.1, -1.9, 1.2, -0.4));
  const Eigen::Isometry3d before = g.worldTransform(cup);
  g.reparent(cup, cupboard);
  EXPECT_EQ(g.node(cup).parent, cupboard);
  EXPECT_TRUE(g.worldTransform(cup).isApprox(before, 1e-12));
  // T_cup_in_cupboard = T_cupboard^-1 * T_cup
  EXPECT_TRUE(
      g.node(cup).T_parent_node.isApprox(g.worldTransform(cupboard).inverse() * before, 1e-12));
  g.reparent(cup, kWorldNode);
  EXPECT_TRUE(g.worldTransform(cup).isApprox(before, 1e-12));
  EXPECT_TRUE(g.node(cupboard).children.empty());
}

TEST(SceneGraph, RefusesCycles) {
  SceneGraph g;
  const NodeId a = g.add("a", "", kWorldNode, pose(1, 0, 0, 0));
  const NodeId b = g.add("b", "", a, pose(1, 0, 0, 0));
  EXPECT_THROW(g.reparent(a, b), std::invalid_argument);
  EXPECT_THROW(g.reparent(a, a), std::invalid_argument);
  EXPECT_THROW(g.remove(kWorldNode), std::invalid_argument);
}

TEST(SceneGraph, RemoveLiftsChildrenKeepingWorldPose) {
  SceneGraph g;
  const NodeId klt = g.add("klt", "klt", kWorldNode, pose(1, 2, 0.8, 0.5));
  const NodeId relay = g.add("relay", "relay", klt, pose(0.02, 0.01, 0, 0.2));
  const Eigen::Isometry3d before = g.worldTransform(relay);
  g.remove(klt);
  EXPECT_FALSE(g.contains(klt));
  EXPECT_EQ(g.node(relay).parent, kWorldNode);
  EXPECT_TRUE(g.worldTransform(relay).isApprox(before, 1e-12));
  EXPECT_THROW(g.node(klt), std::out_of_range);
}

TEST(SceneGraph, RejectsNonFiniteTransforms) {
  SceneGraph g;
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::nan("");
  EXPECT_THROW(g.add("x", "", kWorldNode, bad), std::invalid_argument);
  const NodeId n = g.add("y", "", kWorldNode, Eigen::Isometry3d::Identity());
  EXPECT_THROW(g.setLocalTransform(n, bad), std::invalid_argument);
}

}  // namespace
}  // namespace sgt
