// Range sensors other than the configured VLP-16 grid: clouds of a VLP-32C and an Ouster OS1-64
// (simulated in the generated building) and a Tiago's planar base laser become one ray per return
// and localize the robot from a 30 cm / 5 deg start; the real Luminar bag's unorganized clouds and
// laser scans go through every stage of the pipeline.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>
#include <variant>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/registration/localizer.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt::ros {
namespace {

constexpr NodeId kMap = 1;

SpinningLidarModel scanner(int columns, int rings, double phi_min_deg, double phi_max_deg) {
  SpinningLidarModel m;
  m.columns = columns, m.rings = rings, m.theta_inc = 2.0 * M_PI / columns;
  m.phi_min = phi_min_deg * M_PI / 180.0, m.phi_max = phi_max_deg * M_PI / 180.0;
  return m;
}

class RangeSensorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.setStaticMap(std::make_shared<TriangleMesh>(test::coarseBuilding().mesh), kMap);
    scene_.commit();
    T_map_base_ = test::poseXyzYaw(test::coarseBuilding().robot_start.cast<double>(), 0.3);
  }

  // A robot 30 cm / 5 deg off its true pose, as in the localizer's own test.
  Eigen::Isometry3d offPrior(double direction) const {
    Eigen::Isometry3d prior = T_map_base_;
    prior.translation() += 0.30 * Eigen::Vector3d(std::cos(direction), std::sin(direction), 0.0);
    prior.linear() =
        Eigen::AngleAxisd(5.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * prior.linear();
    return prior;
  }

  void expectLocalizes(const RangeMeasurements& m, const Eigen::Isometry3d& prior) const {
    const LocalizeResult r = Localizer().localize(scene_, {m}, prior);
    ASSERT_EQ(r.status, LocalizeStatus::kOk)
        << toString(r.status) << ": " << r.inliers << " inliers of " << r.expected << " expected, "
        << r.rays_cast << " rays cast, ended "
        << (r.T_map_base_estimate.translation() - T_map_base_.translation()).norm() << " m off";
    EXPECT_LT((r.T_map_base.translation() - T_map_base_.translation()).norm(), 0.02);
    EXPECT_LT(test::rotationErrorDeg(r.T_map_base.linear(), T_map_base_.linear()), 0.5);
  }

  RaycastScene scene_;
  Eigen::Isometry3d T_map_base_;
  const Eigen::Isometry3d T_base_lidar_ = test::poseXyzYaw({0.1, 0.0, 0.9});
};

TEST_F(RangeSensorTest, CloudsOfOtherScannersGetARayPerPointAndLocalize) {
  const SpinningLidarModel configured = SpinningLidarModel::vlp16();
  const auto configured_rays = std::make_shared<const SensorRays>(makeRays(configured));
  const std::pair<const char*, SpinningLidarModel> scanners[] = {
      {"VLP-32C", scanner(1800, 32, -25.0, 15.0)}, {"OS1-64", scanner(1024, 64, -16.6, 16.6)}};
  for (const auto& [name, model] : scanners) {
    SCOPED_TRACE(name);
    const SensorRays rays = makeRays(model);
    const SimulatedScan s = simulate(scene_, rays, T_map_base_ * T_base_lidar_);
    sensor_msgs::PointCloud2 cloud = cloudFromRanges(s.range, rays, {});
    for (const bool organized : {true, false}) {
      if (!organized)
        cloud.height = 1, cloud.width = rays.size(), cloud.row_step = cloud.data.size();
      RangeMeasurements m = measurementsFromCloud(cloud, configured, configured_rays,
                                                  offPrior(organized ? 1.0 : 4.0) * T_base_lidar_);
      EXPECT_TRUE(std::holds_alternative<PointRays>(m.model));
      EXPECT_EQ(m.size(), m.validCount());  // only returns became rays
      EXPECT_GT(m.size(), rays.size() / 3);
      addRangeNoise(m, 0.01, 7);
      expectLocalizes(m, offPrior(organized ? 1.0 : 4.0));
    }
  }
}

TEST_F(RangeSensorTest, APlanarBaseLaserScanLocalizes) {
  // A Tiago's base laser: 666 beams over 220 deg, 0.1 m above the floor, 0.05-25 m.
  sensor_msgs::LaserScan scan;
  scan.angle_min = -1.9198f, scan.angle_increment = 0.00577f, scan.range_min = 0.05f,
  scan.range_max = 25.0f;
  std::vector<Eigen::Vector3f> directions;
  for (int i = 0; i < 666; ++i) {
    const double a = scan.angle_min + i * double(scan.angle_increment);
    directions.emplace_back(std::cos(a), std::sin(a), 0.0f);
  }
  const Eigen::Isometry3d T_base_laser = test::poseXyzYaw({0.2, 0.0, 0.1});
  const SimulatedScan s = simulate(scene_, makeRays(directions), T_map_base_ * T_base_laser);
  scan.ranges = s.range;
  const Eigen::Isometry3d prior = offPrior(2.0);
  RangeMeasurements m = measurementsFromScan(scan, prior * T_base_laser);
  EXPECT_GT(m.validCount(), 300u);
  addRangeNoise(m, 0.01, 3);
  expectLocalizes(m, prior);
}

// ../shared/data/real/luminar_bag: a real unorganized LiDAR (about 36k points a scan, LZ4 chunks)
// and a laser scan, with no map of the place: read, turned into rays, and through every stage
// (localization, refinement, pre-segmentation, relations) on a floor as the map.
TEST(RealLidar, TheLuminarBagGoesThroughEveryStage) {
  const std::string path =
      std::string(SGT_SOURCE_DIR) + "/../shared/data/real/luminar_bag/luminar.bag";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present: skipped";
  rosbag::Bag bag(path);
  const auto floor = std::make_shared<TriangleMesh>(makeBox({400.0f, 400.0f, 0.1f}));
  FramePipeline pipeline(test::benchScene()->catalog, floor);
  const SpinningLidarModel configured = SpinningLidarModel::vlp16();
  const auto configured_rays = std::make_shared<const SensorRays>(makeRays(configured));
  std::size_t clouds = 0, scans = 0;
  for (const rosbag::MessageInstance& msg : rosbag::View(bag)) {
    PipelineFrame frame;  // the scans come 7 s after the clouds: frames of their own
    if (const auto cloud = msg.instantiate<sensor_msgs::PointCloud2>()) {
      frame.stamp = cloud->header.stamp.toSec();
      frame.measurements.push_back(measurementsFromCloud(*cloud, configured, configured_rays,
                                                         Eigen::Isometry3d::Identity()));
      EXPECT_TRUE(std::holds_alternative<PointRays>(frame.measurements.back().model));
      // Returns beyond the configured 100 m range_max are no return.
      EXPECT_GT(frame.measurements.back().validCount(), 25000u)
          << "of " << cloud->width * cloud->height << " points";
      ++clouds;
    } else if (const auto scan = msg.instantiate<sensor_msgs::LaserScan>()) {
      frame.stamp = 100.0 + scan->header.stamp.toSec();
      frame.measurements.push_back(measurementsFromScan(*scan, Eigen::Isometry3d::Identity()));
      EXPECT_EQ(frame.measurements.back().size(), 90u);
      ++scans;
    } else {
      continue;
    }
    const PipelineResult r = pipeline.process(std::move(frame));
    ASSERT_EQ(r.presegmentation.size(), 1u);
    EXPECT_EQ(r.presegmentation.front().label.size(), r.measurements.front().size());
  }
  EXPECT_EQ(clouds, 5u);
  EXPECT_EQ(scans, 5u);
}

}  // namespace
}  // namespace sgt::ros
