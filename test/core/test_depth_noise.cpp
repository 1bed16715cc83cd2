// The depth noise measured on the static map against the noise the simulation added: found from
// a start far too small or too large, and not moved by unknown things in front of the map.
#include <gtest/gtest.h>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/segmentation/depth_noise.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr NodeId kMap = 1, kUnknown = 40;

class DepthNoiseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.setStaticMap(std::make_shared<TriangleMesh>(test::coarseBuilding().mesh), kMap);
    base_ = test::coarseBuilding().robot_start.cast<double>();
    scene_.commit();
  }

  // A depth image from 1.2 m above the robot's start, looking 2 m ahead and down, with noise
  // sigma_at_1m * z^2; with `person`, a person-sized cylinder 1.2 m ahead hides part of the map.
  RangeMeasurements image(double sigma_at_1m, bool person) {
    if (person) {
      scene_.addInstance(
          kUnknown, scene_.addMesh(std::make_shared<TriangleMesh>(makeCylinder(0.3f, 1.75f, 48))),
          test::poseXyzYaw(base_ + Eigen::Vector3d(1.2, -0.2, 0.875)));
      scene_.commit();
    }
    const Eigen::Isometry3d T =
        opticalLookAt(base_ + Eigen::Vector3d(0, 0, 1.2), base_ + Eigen::Vector3d(2.0, -0.4, 0.4));
    const SimulatedScan s = simulate(scene_, *rays_, T);
    if (person) {
      unknown_share_ = 0.0;
      for (NodeId n : s.node) unknown_share_ += n == kUnknown;
      unknown_share_ /= s.node.size();
      scene_.setInstanceEnabled(kUnknown, false);  // the tracker does not know it
      scene_.commit();
    }
    RangeMeasurements m = fromDepthImage(cam_, rays_, depthImage(s, *rays_), T);
    addDepthNoise(m, sigma_at_1m, 7);
    return m;
  }

  PinholeModel cam_ = PinholeModel::xtion();
  std::shared_ptr<SensorRays> rays_ = std::make_shared<SensorRays>(makeRays(cam_));
  RaycastScene scene_;
  Eigen::Vector3d base_;
  double unknown_share_ = 0.0;
};

TEST_F(DepthNoiseTest, MeasuresTheNoiseOfTheImageWhateverTheSetting) {
  for (const double truth : {0.0015, 0.0045}) {
    const RangeMeasurements m = image(truth, false);
    // Along the ray the noise is sigma * z * r (r >= z off the axis): within 15 % of sigma, with
    // the setting right, 3x too small or 3x too large.
    for (const double setting : {truth, truth / 3, truth * 3}) {
      const auto s = measureDepthSigmaAt1m(scene_, m, static_cast<float>(setting));
      ASSERT_TRUE(s.has_value());
      EXPECT_NEAR(*s, truth, 0.15 * truth) << "truth " << truth << " setting " << setting;
    }
  }
}

// A map 5 cm off the world everywhere (or a camera pose that far off): the measurement stays
// within the window the setting gives, not growing with what it measures.
TEST_F(DepthNoiseTest, AMapThatMissesTheWorldCannotWidenItWithoutBound) {
  RangeMeasurements m = image(0.0015, false);
  m.T_world_sensor.translation().z() += 0.05;
  const auto s = measureDepthSigmaAt1m(scene_, m, 0.0015f);
  ASSERT_TRUE(s.has_value());
  EXPECT_LT(*s, 10 * 0.0015 * 1.4826);
}

TEST_F(DepthNoiseTest, UnknownThingsInFrontOfTheMapDoNotMoveIt) {
  const RangeMeasurements m = image(0.003, true);
  ASSERT_GT(unknown_share_, 0.1);  // the person is in view
  const auto s = measureDepthSigmaAt1m(scene_, m, 0.003f);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(*s, 0.003, 0.15 * 0.003);
}

TEST_F(DepthNoiseTest, MeasuresNothingWithoutADepthImageOrAMap) {
  const RangeMeasurements depth = image(0.002, false);
  auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const RangeMeasurements scan =
      fromRanges(SpinningLidarModel::vlp16(), lidar_rays,
                 std::vector<float>(lidar_rays->size(), 3.0f), depth.T_world_sensor);
  EXPECT_FALSE(measureDepthSigmaAt1m(scene_, scan, 0.002f).has_value());
  RaycastScene no_map;
  no_map.commit();
  EXPECT_FALSE(measureDepthSigmaAt1m(no_map, depth, 0.002f).has_value());
  DepthNoiseOptions few;
  few.min_rays = static_cast<int>(depth.size());  // more than a strided cast can give
  EXPECT_FALSE(measureDepthSigmaAt1m(scene_, depth, 0.002f, few).has_value());
}

}  // namespace
}  // namespace sgt
