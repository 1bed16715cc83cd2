// presenceScore against ground truth: a model where its object is shows much; a second model of
// the same object, or a model where only the table is, shows nothing or contradicts the depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_graph_tracker/registration/twin_evidence.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr NodeId kObject = 10;
constexpr NodeId kSecond = 11;

struct View {
  std::unique_ptr<RaycastScene> scene;
  RangeMeasurements depth;
};

// `name` on the table at (0.05, 0, top), seen from 1 m at 40 deg down with the demo's noise
// (1.5 mm at 1 m): the depth is rendered with the object alone in the scene.
View tableView(const std::string& name) {
  const ObjectClass& c = test::packageCatalog().get(name);
  const Eigen::Isometry3d truth =
      test::poseXyzYaw(Eigen::Vector3d(0.05, 0.0, 0.75 - c.box.min().z()), 0.3);
  View v{test::objectOnTable(c, kObject, truth), {}};
  v.depth = test::xtionView(*v.scene, {0.0, 0.75, 1.4}, {0.05, 0.0, 0.75}, 0.0015, 7);
  return v;
}

class Presence : public ::testing::TestWithParam<const char*> {};

TEST_P(Presence, AModelWhereItsObjectIsShowsMuch) {
  View v = tableView(GetParam());
  const ObjectClass& c = test::packageCatalog().get(GetParam());
  const Eigen::Isometry3d truth = v.scene->instancePose(kObject);
  EXPECT_GT(presenceScore(*v.scene, kObject, c.box, {v.depth}, RangeNoise{}), 5.0);
  EXPECT_TRUE(v.scene->instancePose(kObject).isApprox(truth));  // left where it was, enabled
  RayHits hits;
  hits.resize(v.depth.rays->width, v.depth.rays->height);
  v.scene->cast(*v.depth.rays, v.depth.T_world_sensor, hits);
  EXPECT_TRUE(std::find(hits.node.begin(), hits.node.end(), kObject) != hits.node.end());
}

TEST_P(Presence, ASecondModelOfATrackedObjectShowsNothing) {
  View v = tableView(GetParam());
  const ObjectClass& c = test::packageCatalog().get(GetParam());
  v.scene->addInstance(kSecond, v.scene->instanceMesh(kObject), v.scene->instancePose(kObject));
  v.scene->commit();
  EXPECT_LT(std::abs(presenceScore(*v.scene, kSecond, c.box, {v.depth}, RangeNoise{})), 1.0);
  EXPECT_LT(std::abs(presenceScore(*v.scene, kObject, c.box, {v.depth}, RangeNoise{})), 1.0);
}

TEST_P(Presence, AModelWhereOnlyTheTableIsContradictsTheDepth) {
  View v = tableView(GetParam());
  const ObjectClass& c = test::packageCatalog().get(GetParam());
  const Eigen::Isometry3d beside =
      test::poseXyzYaw(Eigen::Vector3d(-0.35, 0.1, 0.75 - c.box.min().z()), 0.3);
  v.scene->addInstance(kSecond, v.scene->instanceMesh(kObject), beside);
  v.scene->commit();
  EXPECT_LT(presenceScore(*v.scene, kSecond, c.box, {v.depth}, RangeNoise{}), -5.0);
}

INSTANTIATE_TEST_SUITE_P(Classes, Presence,
                         ::testing::Values("materialbox", "multimeter", "relay", "screwdriver"));

}  // namespace
}  // namespace sgt
