// The frame assembler: which hypotheses and which scan go with a depth image, the LiDAR model from
// the options, and bad input that costs only itself.
#include <gtest/gtest.h>

#include <boost/make_shared.hpp>
#include <limits>

#include "scene_graph_tracker/ros/frame_assembler.hpp"

namespace sgt::ros {
namespace {

const std::string kCamera = "camera", kLidar = "lidar";

// Every frame sits 1 m above the previous one in z: odom <- base is the identity, base <- camera
// and odom <- camera a 1 m lift, odom <- lidar 2 m.
Eigen::Isometry3d lift(double z) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().z() = z;
  return T;
}

FrameAssembler::Lookup fixedFrames() {
  return [](const std::string& target, const std::string& source, const ::ros::Time&) {
    if (source == kCamera) return lift(1.0);
    if (source == kLidar) return lift(2.0);
    if (target == source || source == "base_link") return Eigen::Isometry3d::Identity();
    throw std::runtime_error("no transform " + target + " <- " + source);
  };
}

sensor_msgs::CameraInfo smallCamera() {
  PinholeModel cam;
  cam.width = 8, cam.height = 6, cam.fx = cam.fy = 10, cam.cx = 4, cam.cy = 3;
  return toCameraInfo(cam);
}

sensor_msgs::Image depthAt(double stamp) {
  sensor_msgs::Image img = depthToImage(std::vector<float>(48, 1.5f), 8, 6);
  img.header.stamp = ::ros::Time(stamp);
  img.header.frame_id = kCamera;
  return img;
}

scene_graph_tracker::PoseHypothesisArray::Ptr hypothesesAt(double stamp, int count,
                                                           double x = 0.5) {
  auto h = boost::make_shared<scene_graph_tracker::PoseHypothesisArray>();
  h->header.stamp = ::ros::Time(stamp);
  h->header.frame_id = kCamera;
  for (int i = 0; i < count; ++i) {
    scene_graph_tracker::PoseHypothesis p;
    p.class_name = "klt";
    p.pose.orientation.w = 1.0;
    p.pose.position.x = x;
    p.score = 0.9;
    h->hypotheses.push_back(p);
  }
  return h;
}

sensor_msgs::PointCloud2::Ptr cloudAt(double stamp, const SpinningLidarModel& model) {
  const SensorRays rays = makeRays(model);
  auto cloud = boost::make_shared<sensor_msgs::PointCloud2>(
      cloudFromRanges(std::vector<float>(rays.size(), 3.0f), rays, {}));
  cloud->header.stamp = ::ros::Time(stamp);
  cloud->header.frame_id = kLidar;
  return cloud;
}

TEST(FrameAssembler, TakesTheClosestHypothesisArrayOnceInTheBaseFrame) {
  FrameAssembler assembler({}, fixedFrames());
  assembler.addHypotheses(hypothesesAt(0.9, 3));  // too old for the image at 1.0 ...
  auto closest = hypothesesAt(0.98, 2);           // ... this one is closest ...
  closest->hypotheses[1].up_to_box_half_turns = true;
  assembler.addHypotheses(closest);
  assembler.addHypotheses(hypothesesAt(1.05, 1));  // ... and this one belongs to a later image
  const AssembledFrame a = assembler.assemble(depthAt(1.0), smallCamera());
  ASSERT_EQ(a.frame.hypotheses.size(), 2u);
  EXPECT_NEAR(a.frame.hypotheses[0].T_base_object.translation().z(), 1.0, 1e-12);  // base <- camera
  EXPECT_FALSE(a.frame.hypotheses[0].up_to_box_half_turns);
  EXPECT_TRUE(a.frame.hypotheses[1].up_to_box_half_turns);
  ASSERT_EQ(a.frame.measurements.size(), 1u);
  EXPECT_NEAR(a.frame.measurements[0].T_world_sensor.translation().z(), 1.0, 1e-12);
  // Arrays up to the image's stamp are used up; the later one is still there for its image.
  EXPECT_EQ(assembler.assemble(depthAt(1.03), smallCamera()).frame.hypotheses.size(), 1u);
  EXPECT_TRUE(assembler.assemble(depthAt(1.5), smallCamera()).frame.hypotheses.empty());
}

// The robot drives along x at 1 m/s (odom <- base a translation by the time); the camera is 1 m
// above the base.
FrameAssembler::Lookup drivingBase() {
  const auto inOdom = [](const std::string& frame, double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (frame == "odom") return T;
    T.translation().x() = t;
    if (frame == kCamera) T = T * lift(1.0);
    if (frame != kCamera && frame != "base_link") throw std::runtime_error("no frame " + frame);
    return T;
  };
  return [inOdom](const std::string& target, const std::string& source, const ::ros::Time& t) {
    return Eigen::Isometry3d(inOdom(target, t.toSec()).inverse() * inOdom(source, t.toSec()));
  };
}

// A detector slower than the camera: the array the image gets was seen 20 ms earlier, when the
// robot stood 2 cm further back. Its objects are where the detector saw them, in the base frame
// of the image; an array in a frame without a transform costs itself, not the frame.
TEST(FrameAssembler, AnArrayFromAnotherTimeGoesThroughTheOdometry) {
  FrameAssembler assembler({}, drivingBase());
  assembler.addHypotheses(hypothesesAt(0.98, 1, 0.5));
  AssembledFrame a = assembler.assemble(depthAt(1.0), smallCamera());
  ASSERT_EQ(a.frame.hypotheses.size(), 1u);
  EXPECT_NEAR(a.frame.hypotheses[0].T_base_object.translation().x(), 0.48, 1e-9);
  EXPECT_NEAR(a.frame.hypotheses[0].T_base_object.translation().z(), 1.0, 1e-9);
  assembler.addHypotheses(hypothesesAt(1.1, 1, 0.5));  // of the image's own stamp
  a = assembler.assemble(depthAt(1.1), smallCamera());
  ASSERT_EQ(a.frame.hypotheses.size(), 1u);
  EXPECT_NEAR(a.frame.hypotheses[0].T_base_object.translation().x(), 0.5, 1e-9);
  auto elsewhere = hypothesesAt(1.19, 2, 0.5);
  elsewhere->header.frame_id = "no_tf";
  assembler.addHypotheses(elsewhere);
  a = assembler.assemble(depthAt(1.2), smallCamera());
  EXPECT_TRUE(a.frame.hypotheses.empty());
  EXPECT_EQ(a.frame.measurements.size(), 1u);
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_NE(a.warnings[0].find("no_tf"), std::string::npos) << a.warnings[0];
}

TEST(FrameAssembler, TakesTheNewestScanNotLaterThanTheImageWithTheConfiguredModel) {
  FrameAssemblerOptions options;
  options.lidar.columns = 360, options.lidar.rings = 32, options.lidar.theta_inc = 2.0 * M_PI / 360;
  FrameAssembler assembler(options, fixedFrames());
  assembler.addCloud(cloudAt(0.8, options.lidar));
  assembler.addCloud(cloudAt(0.95, options.lidar));
  assembler.addCloud(cloudAt(1.2, options.lidar));
  const AssembledFrame a = assembler.assemble(depthAt(1.0), smallCamera());
  ASSERT_EQ(a.frame.measurements.size(), 2u);
  ASSERT_TRUE(a.cloud);
  EXPECT_DOUBLE_EQ(a.cloud->header.stamp.toSec(), 0.95);
  EXPECT_EQ(a.frame.measurements[1].size(), 360u * 32u);
  EXPECT_NEAR(a.frame.measurements[1].T_world_sensor.translation().z(), 2.0, 1e-12);
  EXPECT_EQ(assembler.assemble(depthAt(1.1), smallCamera()).frame.measurements.size(),
            1u);  // used once
  EXPECT_EQ(assembler.assemble(depthAt(1.3), smallCamera()).frame.measurements.size(), 2u);
}

TEST(FrameAssembler, ABadHypothesisOrScanCostsOnlyItself) {
  FrameAssembler assembler({}, fixedFrames());
  auto h = hypothesesAt(1.0, 3);
  h->hypotheses[0].pose.position.y = std::numeric_limits<double>::quiet_NaN();
  h->hypotheses[1].pose.orientation.w = 0.0;  // a zero quaternion
  assembler.addHypotheses(h);
  sensor_msgs::PointCloud2::Ptr no_points = boost::make_shared<sensor_msgs::PointCloud2>();
  no_points->header.stamp = ::ros::Time(0.99);
  assembler.addCloud(no_points);
  const AssembledFrame a = assembler.assemble(depthAt(1.0), smallCamera());
  EXPECT_EQ(a.frame.hypotheses.size(), 1u);
  EXPECT_EQ(a.frame.measurements.size(), 1u);  // the depth image
  EXPECT_EQ(a.warnings.size(), 3u);
}

TEST(FrameAssembler, AnImageItCannotPlaceThrows) {
  FrameAssembler assembler({}, fixedFrames());
  sensor_msgs::Image img = depthAt(1.0);
  img.header.frame_id = "unknown";
  EXPECT_THROW(assembler.assemble(img, smallCamera()), std::runtime_error);
  sensor_msgs::Image wrong_size = depthToImage(std::vector<float>(12, 1.0f), 4, 3);
  wrong_size.header = depthAt(1.0).header;
  EXPECT_THROW(assembler.assemble(wrong_size, smallCamera()), ConversionError);
}

}  // namespace
}  // namespace sgt::ros
