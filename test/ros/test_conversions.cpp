// Message <-> core conversions: round trips and the errors bad messages must give.
#include <gtest/gtest.h>
#include <scene_graph_tracker/TrackedObject.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <variant>

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

TEST(Conversions, PoseRoundTrip) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(1, -2, 3);
  EXPECT_TRUE(toEigen(toPose(T)).isApprox(T, 1e-12));
  EXPECT_TRUE(toEigen(toTransform(T)).isApprox(T, 1e-12));
  geometry_msgs::Pose zero;
  zero.orientation.w = 0;
  EXPECT_THROW(toEigen(zero), ConversionError);
}

// make fuzz (semap_bridge): an infinite component has an infinite norm and gave a NaN rotation.
TEST(Conversions, AQuaternionWithAnInfiniteComponentIsRejectedAHugeOneNormalized) {
  geometry_msgs::Pose p;
  p.orientation.w = 1.0, p.orientation.x = std::numeric_limits<double>::infinity();
  EXPECT_THROW(toEigen(p), ConversionError);
  p.orientation.w = 1e300, p.orientation.x = 1e300;  // its squared norm overflows
  const Eigen::Isometry3d T = toEigen(p);
  EXPECT_TRUE(T.matrix().allFinite());
  EXPECT_TRUE(T.linear().isApprox(
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix(), 1e-12));
}

// make fuzz (images): cv_bridge checks height x step in 32 bits; 16384 rows of step 2^18 + 1
// wrap around to 16384 bytes, which it then read rows beyond.
TEST(Conversions, AColourImageWhoseSizeWrapsIn32BitsIsRejected) {
  PinholeModel cam;
  cam.width = 4, cam.height = 16384;
  sensor_msgs::Image img;
  img.width = 4, img.height = 16384, img.encoding = sensor_msgs::image_encodings::RGB8;
  img.step = (1u << 18) + 1;
  img.data.resize(16384);
  EXPECT_THROW(rgbFromImage(img, cam), ConversionError);
  img.step = 12, img.data.resize(12 * 16384);
  EXPECT_EQ(rgbFromImage(img, cam).rows, 16384);
}

TEST(Conversions, CameraInfoRoundTripAndBadInfo) {
  PinholeModel cam;
  cam.fx = 500, cam.fy = 510, cam.cx = 300, cam.cy = 200;
  const PinholeModel back = toPinhole(toCameraInfo(cam));
  EXPECT_EQ(back.width, 640);
  EXPECT_DOUBLE_EQ(back.fy, 510);
  EXPECT_DOUBLE_EQ(back.cx, 300);
  sensor_msgs::CameraInfo empty;
  EXPECT_THROW(toPinhole(empty), ConversionError);
}

TEST(Conversions, DepthImagesIn32FAnd16U) {
  PinholeModel cam;
  cam.width = 4, cam.height = 2;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> depth = {1.0f, 2.5f, nan, 0.75f, 3.0f, 0.0f, 1.25f, 4.0f};
  const std::vector<float> back = depthFromImage(depthToImage(depth, 4, 2), cam);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (std::isfinite(depth[i]) && depth[i] > 0)
      EXPECT_FLOAT_EQ(back[i], depth[i]);
    else
      EXPECT_TRUE(std::isnan(back[i])) << i;  // 0 and NaN both mean "no return"
  }
  sensor_msgs::Image mm;
  mm.width = 4, mm.height = 2, mm.step = 8, mm.encoding = sensor_msgs::image_encodings::TYPE_16UC1;
  mm.data.assign(16, 0);
  mm.data[0] = 0xE8, mm.data[1] = 0x03;  // 1000 mm
  const std::vector<float> m = depthFromImage(mm, cam);
  EXPECT_FLOAT_EQ(m[0], 1.0f);
  EXPECT_TRUE(std::isnan(m[1]));
}

TEST(Conversions, BadDepthImagesAreRejectedWithAReason) {
  PinholeModel cam;
  cam.width = 4, cam.height = 2;
  sensor_msgs::Image img = depthToImage(std::vector<float>(8, 1.0f), 4, 2);
  img.encoding = "rgb8";
  try {
    depthFromImage(img, cam);
    FAIL();
  } catch (const ConversionError& e) {
    EXPECT_NE(std::string(e.what()).find("rgb8"), std::string::npos);
  }
  cam.width = 5;
  try {
    depthFromImage(depthToImage(std::vector<float>(8, 1.0f), 4, 2), cam);
    FAIL();
  } catch (const ConversionError& e) {
    EXPECT_NE(std::string(e.what()).find("4x2"), std::string::npos);
  }
  cam.width = 4;
  sensor_msgs::Image short_data = depthToImage(std::vector<float>(8, 1.0f), 4, 2);
  short_data.data.resize(10);
  EXPECT_THROW(depthFromImage(short_data, cam), ConversionError);
}

TEST(Conversions, LidarCloudOrganizedAndUnorganized) {
  const SpinningLidarModel model = SpinningLidarModel::vlp16();
  const auto rays = std::make_shared<const SensorRays>(makeRays(model));
  std::vector<float> ranges(rays->size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < ranges.size(); i += 7) ranges[i] = 1.0f + 0.001f * (i % 1000);
  const sensor_msgs::PointCloud2 cloud = cloudFromRanges(ranges, *rays, {});
  const RangeMeasurements grid = measurementsFromCloud(cloud, model, rays, kIdentity);
  EXPECT_TRUE(std::holds_alternative<SpinningLidarModel>(grid.model));
  EXPECT_EQ(grid.rays, rays);
  ASSERT_EQ(grid.range.size(), ranges.size());
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (std::isfinite(ranges[i]))
      EXPECT_NEAR(grid.range[i], ranges[i], 1e-5f);
    else
      EXPECT_TRUE(std::isnan(grid.range[i]));
  }
  // The same points as one unorganized row: one ray per point with a return, through the point.
  sensor_msgs::PointCloud2 flat = cloud;
  flat.height = 1, flat.width = cloud.width * cloud.height,
  flat.row_step = flat.width * flat.point_step;
  const RangeMeasurements points = measurementsFromCloud(flat, model, rays, kIdentity);
  EXPECT_TRUE(std::holds_alternative<PointRays>(points.model));
  std::size_t k = 0;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (!std::isfinite(ranges[i])) continue;
    ASSERT_LT(k, points.size());
    EXPECT_LT((points.pointInSensor(k) - rays->directions[i] * ranges[i]).norm(), 1e-5f);
    ++k;
  }
  EXPECT_EQ(k, points.size());
  sensor_msgs::PointCloud2 no_xyz;
  EXPECT_THROW(measurementsFromCloud(no_xyz, model, rays, kIdentity), ConversionError);
}

TEST(Conversions, CloudsOfOtherScannersAndFloat64PointsGetARayPerPoint) {
  sensor_msgs::PointCloud2 cloud;  // an Ouster-like 64 x 4 organized cloud of float64 points
  cloud.height = 64, cloud.width = 4;
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2Fields(3, "x", 1, sensor_msgs::PointField::FLOAT64, "y", 1,
                           sensor_msgs::PointField::FLOAT64, "z", 1,
                           sensor_msgs::PointField::FLOAT64);
  std::vector<Eigen::Vector3d> truth;
  for (std::size_t i = 0; i < 256; ++i) {
    const Eigen::Vector3d p(2.0 + 0.01 * i, -1.0 + 0.005 * i, i % 5 == 0 ? NAN : 0.3);
    std::memcpy(cloud.data.data() + i * cloud.point_step, p.data(), 24);
    if (p.allFinite()) truth.push_back(p);
  }
  const auto rays = std::make_shared<const SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const RangeMeasurements m =
      measurementsFromCloud(cloud, SpinningLidarModel::vlp16(), rays, kIdentity);
  EXPECT_TRUE(std::holds_alternative<PointRays>(m.model));
  ASSERT_EQ(m.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    EXPECT_LT((m.pointInSensor(i).cast<double>() - truth[i]).norm(), 1e-5);
  sensor_msgs::PointCloud2 mixed = cloud;
  mixed.fields[2].datatype = sensor_msgs::PointField::FLOAT32;
  EXPECT_THROW(measurementsFromCloud(mixed, SpinningLidarModel::vlp16(), rays, kIdentity),
               ConversionError);
}

TEST(Conversions, LaserScanBeamsBecomeRaysInTheScanPlane) {
  sensor_msgs::LaserScan scan;
  scan.header.frame_id = "base_laser_link";
  scan.angle_min = -1.0f, scan.angle_increment = 0.5f, scan.range_min = 0.05f,
  scan.range_max = 25.0f;
  scan.ranges = {1.0f, 2.0f, NAN, 30.0f, 0.01f};  // the last three are no returns
  const RangeMeasurements m = measurementsFromScan(scan, kIdentity);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m.validCount(), 2u);
  EXPECT_LT((m.pointInSensor(0) - Eigen::Vector3f(std::cos(-1.0f), std::sin(-1.0f), 0)).norm(),
            1e-6f);
  EXPECT_LT(
      (m.pointInSensor(1) - 2.0f * Eigen::Vector3f(std::cos(-0.5f), std::sin(-0.5f), 0)).norm(),
      1e-6f);
  EXPECT_EQ(m.sensor, "base_laser_link");
  sensor_msgs::LaserScan bad = scan;
  bad.angle_increment = 0.0f;
  EXPECT_THROW(measurementsFromScan(bad, kIdentity), ConversionError);
  bad = scan;
  bad.range_max = NAN;
  EXPECT_THROW(measurementsFromScan(bad, kIdentity), ConversionError);
}

// An organized cloud of `model` with a return of `range` on every ray.
sensor_msgs::PointCloud2 fullCloud(const SpinningLidarModel& model, float range) {
  const SensorRays rays = makeRays(model);
  return cloudFromRanges(std::vector<float>(rays.size(), range), rays, {});
}

TEST(Conversions, MalformedCloudsAreRejectedNotReadOutOfBounds) {
  SpinningLidarModel model;
  model.columns = 36, model.rings = 4, model.theta_inc = 2.0 * M_PI / 36;
  const sensor_msgs::PointCloud2 good = fullCloud(model, 2.0f);
  const auto rays = std::make_shared<const SensorRays>(makeRays(model));
  ASSERT_EQ(measurementsFromCloud(good, model, rays, kIdentity).size(), 144u);
  sensor_msgs::PointCloud2 bad = good;
  bad.fields[2].offset = bad.point_step - 2;  // z straddles the end of the point
  EXPECT_THROW(measurementsFromCloud(bad, model, rays, kIdentity), ConversionError);
  bad = good;
  bad.point_step = 0;
  EXPECT_THROW(measurementsFromCloud(bad, model, rays, kIdentity), ConversionError);
  bad = good;
  bad.row_step = bad.width * bad.point_step - 1;
  EXPECT_THROW(measurementsFromCloud(bad, model, rays, kIdentity), ConversionError);
  bad = good;
  bad.width = bad.height = 1u << 31;  // width x height x point_step wraps in 32 bits
  EXPECT_THROW(measurementsFromCloud(bad, model, rays, kIdentity), ConversionError);
  bad = good;
  bad.data.resize(bad.data.size() - 1);
  EXPECT_THROW(measurementsFromCloud(bad, model, rays, kIdentity), ConversionError);
}

TEST(Conversions, CloudsWithPaddedRowsAndBigEndianDataReadBack) {
  SpinningLidarModel model;
  model.columns = 36, model.rings = 4, model.theta_inc = 2.0 * M_PI / 36;
  const sensor_msgs::PointCloud2 good = fullCloud(model, 2.0f);
  sensor_msgs::PointCloud2 padded = good;  // 8 bytes of padding after every row
  padded.row_step = good.row_step + 8;
  padded.data.assign(std::size_t(padded.row_step) * padded.height, 0xAB);
  for (std::uint32_t r = 0; r < good.height; ++r)
    std::copy_n(good.data.begin() + r * good.row_step, good.row_step,
                padded.data.begin() + r * padded.row_step);
  const auto rays = std::make_shared<const SensorRays>(makeRays(model));
  sensor_msgs::PointCloud2 big = good;  // every field byte-swapped
  big.is_bigendian = true;
  for (std::size_t p = 0; p + big.point_step <= big.data.size(); p += big.point_step)
    for (const auto& f : big.fields)
      if (f.datatype == sensor_msgs::PointField::FLOAT32)
        std::reverse(big.data.begin() + p + f.offset, big.data.begin() + p + f.offset + 4);
  for (const sensor_msgs::PointCloud2* c : {&padded, &big}) {
    const std::vector<float> r = measurementsFromCloud(*c, model, rays, kIdentity).range;
    ASSERT_EQ(r.size(), 144u);
    for (float v : r) EXPECT_NEAR(v, 2.0f, 1e-5f);
  }
}

TEST(Conversions, CameraInfoDistortion) {
  PinholeModel cam;
  cam.distortion = {-0.28, 0.09, 0.0012, -0.0008, -0.01};
  const sensor_msgs::CameraInfo info = toCameraInfo(cam);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(toPinhole(info).distortion, cam.distortion);
  sensor_msgs::CameraInfo rational = info;
  rational.distortion_model = "rational_polynomial";
  rational.D.resize(8, 0.0);
  EXPECT_THROW(toPinhole(rational), ConversionError);  // rectify first
  rational.D.assign(8, 0.0);
  EXPECT_FALSE(toPinhole(rational).distorted());  // all zero: no lens to model
  sensor_msgs::CameraInfo nan = info;
  nan.D[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(toPinhole(nan), ConversionError);
}

TEST(Conversions, ACameraInfoBeyondAnyCameraIsRejectedBeforeAnythingIsAllocated) {
  PinholeModel cam;
  sensor_msgs::CameraInfo huge = toCameraInfo(cam);
  huge.width = huge.height = 60000;
  EXPECT_THROW(toPinhole(huge), ConversionError);
  sensor_msgs::CameraInfo inf = toCameraInfo(cam);
  inf.K[2] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(toPinhole(inf), ConversionError);
}

// The tracker publishes track states as codes, the detector's schedule reads them back.
TEST(Conversions, TrackStatesRoundTripThroughTheirCodes) {
  for (TrackState s : {TrackState::kTentative, TrackState::kConfirmed, TrackState::kLost})
    EXPECT_EQ(fromStateCode(toStateCode(s)), s) << toString(s);
  EXPECT_EQ(toStateCode(TrackState::kConfirmed), scene_graph_tracker::TrackedObject::CONFIRMED);
  EXPECT_EQ(fromStateCode(200), TrackState::kTentative);
}

}  // namespace
}  // namespace sgt::ros
