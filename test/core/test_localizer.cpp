// Robot localization against the static map: convergence from 30 cm / 5 deg starts in the
// generated building, tracked objects that explain points without pulling the robot, and
// failures that keep the prior (no map in view, only a floor, no valid measurements).
#include <gtest/gtest.h>

#include <random>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/registration/localizer.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr NodeId kMap = 1;

// The generated building (coarser tessellation than the benchmark's, same geometry), a robot
// at its start point with a VLP-16 0.9 m above the base and 1 cm range noise.
class LocalizerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.setStaticMap(std::make_shared<TriangleMesh>(building_->mesh), kMap);
    scene_.commit();
    T_map_base_ = test::poseXyzYaw(building_->robot_start.cast<double>(), 0.3);
    rays_ = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  }

  // The scan the robot measures at its true pose, with the sensor pose of the robot at `prior`.
  RangeMeasurements scanAt(const Eigen::Isometry3d& prior, std::uint32_t seed = 1) const {
    const SimulatedScan s = simulate(scene_, *rays_, T_map_base_ * T_base_lidar_);
    RangeMeasurements m =
        fromRanges(SpinningLidarModel::vlp16(), rays_, s.range, prior * T_base_lidar_);
    addRangeNoise(m, 0.01, seed);
    return m;
  }

  static double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.translation() - b.translation()).norm();
  }

  const Building* building_ = &test::coarseBuilding();
  RaycastScene scene_;
  Eigen::Isometry3d T_map_base_;
  const Eigen::Isometry3d T_base_lidar_ = test::poseXyzYaw({0.1, 0.0, 0.9});
  std::shared_ptr<SensorRays> rays_;
};

TEST_F(LocalizerTest, ConvergesFrom30cmAnd5DegStarts) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  const Localizer localizer;
  for (int trial = 0; trial < 6; ++trial) {
    const double a = angle(rng);
    Eigen::Isometry3d prior = T_map_base_;
    prior.translation() += 0.30 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    prior.linear() =
        Eigen::AngleAxisd((trial % 2 ? 5.0 : -5.0) * M_PI / 180.0, Eigen::Vector3d::UnitZ()) *
        prior.linear();
    const LocalizeResult r = localizer.localize(scene_, {scanAt(prior, trial + 1)}, prior);
    SCOPED_TRACE("trial " + std::to_string(trial));
    ASSERT_EQ(r.status, LocalizeStatus::kOk) << toString(r.status);
    // The goal is 2 cm / 0.5 deg; ~7,000 map points with 1 cm noise average far below
    // that, so anything above 5 mm / 0.1 deg would mean a bias in the pairing.
    EXPECT_LT(translationError(r.T_map_base, T_map_base_), 0.005);
    EXPECT_LT(test::rotationErrorDeg(r.T_map_base.linear(), T_map_base_.linear()), 0.1);
    EXPECT_GT(r.inlier_ratio, 0.9);
    EXPECT_NEAR(r.rmse, 0.01, 0.005);  // the simulated range noise
  }
}

TEST_F(LocalizerTest, ConvergesFromADepthCameraAndAScanTogether) {
  PinholeModel cam = PinholeModel::xtion();
  auto cam_rays = std::make_shared<SensorRays>(makeRays(cam));
  const Eigen::Isometry3d T_base_camera = opticalLookAt({0.1, 0, 1.2}, {1.1, 0, 0.9});
  const SimulatedScan s = simulate(scene_, *cam_rays, T_map_base_ * T_base_camera);
  Eigen::Isometry3d prior = T_map_base_ * test::poseXyzYaw({0.2, -0.2, 0}, 4.0 * M_PI / 180.0);
  RangeMeasurements depth =
      fromDepthImage(cam, cam_rays, depthImage(s, *cam_rays), prior * T_base_camera);
  addDepthNoise(depth, 0.0015, 3);
  const LocalizeResult r = Localizer().localize(scene_, {depth, scanAt(prior)}, prior);
  ASSERT_EQ(r.status, LocalizeStatus::kOk) << toString(r.status);
  EXPECT_LT(translationError(r.T_map_base, T_map_base_), 0.005);
  EXPECT_LT(test::rotationErrorDeg(r.T_map_base.linear(), T_map_base_.linear()), 0.1);
}

TEST_F(LocalizerTest, TrackedObjectsExplainTheirPointsButDoNotPull) {
  // A large crate right beside the robot, tracked 4 cm off its true place (inside the final
  // threshold): if its points pulled the robot, the robot would move with the crate's error.
  const MeshId crate = scene_.addMesh(std::make_shared<TriangleMesh>(makeBox({1.0f, 1.0f, 1.2f})));
  const Eigen::Isometry3d T_true = T_map_base_ * test::poseXyzYaw({1.2, 0.0, 0.6});
  scene_.addInstance(20, crate, T_true);
  scene_.commit();
  Eigen::Isometry3d prior = T_map_base_ * test::poseXyzYaw({0.25, 0.1, 0}, -4.0 * M_PI / 180.0);
  const RangeMeasurements m = scanAt(prior);
  scene_.setInstancePose(20, T_true * test::poseXyzYaw({0.04, 0.04, 0.0}));
  scene_.commit();
  const LocalizeResult r = Localizer().localize(scene_, {m}, prior);
  ASSERT_EQ(r.status, LocalizeStatus::kOk) << toString(r.status);
  EXPECT_LT(translationError(r.T_map_base, T_map_base_), 0.005);
  EXPECT_LT(test::rotationErrorDeg(r.T_map_base.linear(), T_map_base_.linear()), 0.1);
}

TEST_F(LocalizerTest, KeepsThePriorWhenTheScanDoesNotFitTheMap) {
  const Eigen::Isometry3d far_away =
      test::poseXyzYaw({500.0, 500.0, 0.0});  // outside the building: no map hits
  const LocalizeResult r = Localizer().localize(scene_, {scanAt(far_away)}, far_away);
  EXPECT_EQ(r.status, LocalizeStatus::kTooFewInliers);
  EXPECT_TRUE(r.T_map_base.isApprox(far_away));
}

TEST_F(LocalizerTest, KeepsThePriorWhenNoMeasurementIsValid) {
  const Eigen::Isometry3d prior = T_map_base_ * test::poseXyzYaw({0.1, 0, 0});
  RangeMeasurements m = scanAt(prior);
  std::fill(m.range.begin(), m.range.end(), std::numeric_limits<float>::quiet_NaN());
  const LocalizeResult r = Localizer().localize(scene_, {m}, prior);
  EXPECT_EQ(r.status, LocalizeStatus::kTooFewInliers);
  EXPECT_EQ(r.inliers, 0);
  EXPECT_TRUE(r.T_map_base.isApprox(prior));
  EXPECT_EQ(Localizer().localize(scene_, {}, prior).status, LocalizeStatus::kTooFewInliers);
}

TEST(Localizer, FlagsAMapThatOnlyShowsAFloor) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({20, 20, 0.1f})), kMap);
  scene.commit();
  auto rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const Eigen::Isometry3d T_true = test::poseXyzYaw({0, 0, 1.0});
  const SimulatedScan s = simulate(scene, *rays, T_true);
  const Eigen::Isometry3d prior = test::poseXyzYaw({0.2, 0.1, 1.0});
  const LocalizeResult r = Localizer().localize(
      scene, {fromRanges(SpinningLidarModel::vlp16(), rays, s.range, prior)}, prior);
  EXPECT_EQ(r.status, LocalizeStatus::kDegenerate) << toString(r.status);
  EXPECT_TRUE(r.T_map_base.isApprox(prior));
}

}  // namespace
}  // namespace sgt
