// The bridge's message -> rows conversion (no database): world poses through the parent chain,
// unknown classes left out, and a malformed message refused as a whole with a reason.
#include <gtest/gtest.h>

#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/semap/bridge.hpp"
#include "writer_support.hpp"

namespace sgt::ros {
namespace {

scene_graph_tracker::SceneGraphNode node(const std::string& id, const std::string& cls,
                                         const std::string& parent, const Eigen::Vector3d& t) {
  scene_graph_tracker::SceneGraphNode n;
  n.id = id, n.class_name = cls, n.parent = parent;
  n.T_parent_node = toTransform(Eigen::Isometry3d(Eigen::Translation3d(t)));
  return n;
}

const ShapeLookup kShapes = [](const std::string& c) -> std::shared_ptr<const semap::ClassShape> {
  return c == "unknown" ? nullptr : test::boxShape(c, 0.05);
};

TEST(BridgeRows, SceneGraphPosesComposeAlongParentsAndUnknownClassesAreLeftOut) {
  scene_graph_tracker::SceneGraph g;
  g.nodes = {node("relay_1", "relay", "klt_1", {0, 0, 0.1}), node("klt_1", "klt", "map", {1, 2, 0}),
             node("x_1", "unknown", "map", {0, 0, 0})};
  const semap::Frame f = frameFromSceneGraph(g, 12.5, kShapes);
  ASSERT_EQ(f.objects.size(), 2u);
  EXPECT_EQ(f.stamp, 12.5);
  EXPECT_EQ(f.objects[0].id, "relay_1");
  EXPECT_EQ(f.objects[0].parent, "klt_1");
  EXPECT_TRUE(f.objects[0].T_world_object.translation().isApprox(Eigen::Vector3d(1, 2, 0.1)));
}

TEST(BridgeRows, MalformedMessagesAreRefusedWithAReason) {
  scene_graph_tracker::SceneGraph cycle;
  cycle.nodes = {node("a", "klt", "b", {0, 0, 0}), node("b", "klt", "a", {0, 0, 0})};
  EXPECT_THROW(frameFromSceneGraph(cycle, 0, kShapes), ConversionError);
  scene_graph_tracker::SceneGraph twice;
  twice.nodes = {node("a", "klt", "map", {0, 0, 0}), node("a", "klt", "map", {1, 0, 0})};
  EXPECT_THROW(frameFromSceneGraph(twice, 0, kShapes), ConversionError);
  scene_graph_tracker::SceneGraph nan;
  nan.nodes = {node("a", "klt", "map", {std::nan(""), 0, 0})};
  EXPECT_THROW(frameFromSceneGraph(nan, 0, kShapes), ConversionError);

  scene_graph_tracker::TrackedObjectArray zero;  // the quaternion that used to end the node
  zero.objects.resize(1);
  zero.objects[0].id = "klt_1", zero.objects[0].class_name = "klt";
  EXPECT_THROW(frameFromTrackedObjects(zero, 0, kShapes), ConversionError);
  zero.objects[0].pose.pose.orientation.w = 1.0;
  EXPECT_EQ(frameFromTrackedObjects(zero, 0, kShapes).objects.size(), 1u);
  zero.objects[0].id.clear();
  EXPECT_THROW(frameFromTrackedObjects(zero, 0, kShapes), ConversionError);
}

TEST(BridgeRows, NamesAreTextTheDatabaseCanHoldOrTheMessageIsRefused) {
  scene_graph_tracker::SceneGraph g;
  g.nodes = {node("'; DROP TABLE instance;--", "klt", "map", {0, 0, 0}),
             node("Schraubendreher_\xc3\xbc_\xe6\x97\xa5", "klt", "map", {1, 0, 0})};
  EXPECT_EQ(frameFromSceneGraph(g, 0, kShapes).objects.size(), 2u) << "stored as they are";
  for (const std::string bad : {std::string(1 << 20, 'x'), std::string("klt\0_1", 5),
                                std::string("klt_\xff"), std::string("klt_\xe6\x97")}) {
    scene_graph_tracker::SceneGraph b;
    b.nodes = {node(bad, "klt", "map", {0, 0, 0})};
    EXPECT_THROW(frameFromSceneGraph(b, 0, kShapes), ConversionError) << bad.size() << " bytes";
    b.nodes = {node("klt_1", bad, "map", {0, 0, 0})};
    EXPECT_THROW(frameFromSceneGraph(b, 0, kShapes), ConversionError);
  }
}

TEST(BridgeRows, ALongParentChainNeedsNoDeepRecursion) {
  scene_graph_tracker::SceneGraph g;
  for (int i = 0; i < 5000; ++i)
    g.nodes.push_back(node("n" + std::to_string(i), "klt", i ? "n" + std::to_string(i - 1) : "map",
                           {0.001, 0, 0}));
  const semap::Frame f = frameFromSceneGraph(g, 0, kShapes);
  EXPECT_NEAR(f.objects.back().T_world_object.translation().x(), 5.0, 1e-9);
  g.nodes.resize(kMaxFrameObjects + 1, node("extra", "klt", "map", {0, 0, 0}));
  EXPECT_THROW(frameFromSceneGraph(g, 0, kShapes), ConversionError);
}

TEST(BridgeRows, ARobotIdPrefixesItsIdsAndTheParentsThatAreIds) {
  scene_graph_tracker::SceneGraph g;
  g.nodes = {node("relay_1", "relay", "klt_1", {0, 0, 0.1}),
             node("klt_1", "klt", "map", {1, 2, 0})};
  const semap::Frame f = forRobot(frameFromSceneGraph(g, 3.0, kShapes), "tiago_2");
  EXPECT_EQ(f.robot, "tiago_2");
  ASSERT_EQ(f.objects.size(), 2u);
  EXPECT_EQ(f.objects[0].id, "tiago_2/relay_1");
  EXPECT_EQ(f.objects[0].parent, "tiago_2/klt_1");
  EXPECT_EQ(f.objects[1].id, "tiago_2/klt_1");
  EXPECT_EQ(f.objects[1].parent, "map") << "the root frame is no object";
  const semap::Frame alone = forRobot(frameFromSceneGraph(g, 3.0, kShapes), "");
  EXPECT_EQ(alone.objects[0].id, "relay_1");
  EXPECT_THROW(forRobot(alone, "a/b"), ConversionError);
  EXPECT_THROW(forRobot(alone, std::string("a\0b", 3)), ConversionError);
}

}  // namespace
}  // namespace sgt::ros
