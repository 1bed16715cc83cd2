// Sensor models: pinhole (with and without lens distortion) and VLP-16 ray directions match their
// definitions; simulated depth of a known plane equals the analytic depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt {
namespace {

TEST(PinholeModel, RaysProjectBackToTheirPixels) {
  PinholeModel cam;  // 640x480, f 525
  cam.cx = 320.7, cam.cy = 241.2, cam.fy = 530.0;
  const SensorRays rays = makeRays(cam);
  ASSERT_EQ(rays.width, 640);
  ASSERT_EQ(rays.height, 480);
  for (int v : {0, 17, 240, 479})
    for (int u : {0, 99, 320, 639}) {
      const Eigen::Vector3f d = rays.directions[rays.index(u, v)];
      EXPECT_NEAR(d.norm(), 1.0f, 1e-6f);
      EXPECT_GT(d.z(), 0.0f);
      const auto px = cam.project(d.cast<double>());
      ASSERT_TRUE(px);
      EXPECT_NEAR(px->x(), u, 1e-3);
      EXPECT_NEAR(px->y(), v, 1e-3);
    }
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, -1)));
  // The principal point's ray is the optical axis.
  PinholeModel centred;
  centred.cx = 10, centred.cy = 20;
  EXPECT_TRUE(centred.direction(10, 20).isApprox(Eigen::Vector3f::UnitZ()));
  cam.width = 0;
  EXPECT_THROW(makeRays(cam), std::invalid_argument);
}

// A plumb_bob lens (a RealSense colour camera's order of distortion, and stronger): every pixel's
// ray projects back onto it, and project() agrees with OpenCV's projectPoints.
TEST(PinholeModel, DistortedRaysProjectBackAndMatchOpenCv) {
  PinholeModel cam;
  cam.distortion = {-0.28, 0.09, 0.0012, -0.0008, -0.01};
  ASSERT_TRUE(cam.distorted());
  const SensorRays rays = makeRays(cam);
  const cv::Mat K = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << -0.28, 0.09, 0.0012, -0.0008, -0.01);
  double straight_apart = 0.0;  // how far the corner rays are from an undistorted camera's
  for (int v : {0, 17, 240, 479})
    for (int u : {0, 99, 320, 639}) {
      const Eigen::Vector3f d = rays.directions[rays.index(u, v)];
      EXPECT_NEAR(d.norm(), 1.0f, 1e-6f);
      const auto px = cam.project(d.cast<double>() * 2.0);
      ASSERT_TRUE(px);
      EXPECT_NEAR(px->x(), u, 1e-3);
      EXPECT_NEAR(px->y(), v, 1e-3);
      std::vector<cv::Point2d> cv_px;
      cv::projectPoints(std::vector<cv::Point3d>{{d.x(), d.y(), d.z()}}, cv::Vec3d(0, 0, 0),
                        cv::Vec3d(0, 0, 0), K, D, cv_px);
      EXPECT_NEAR(cv_px[0].x, px->x(), 1e-6);
      EXPECT_NEAR(cv_px[0].y, px->y(), 1e-6);
      straight_apart = std::max<double>(
          straight_apart, std::acos(std::min(1.0f, d.dot(PinholeModel().direction(u, v)))));
    }
  EXPECT_GT(straight_apart * 180.0 / M_PI, 2.0);  // the lens matters at the corners
}

TEST(SpinningLidarModel, Vlp16Geometry) {
  const SpinningLidarModel lidar = SpinningLidarModel::vlp16();
  const SensorRays rays = makeRays(lidar);
  ASSERT_EQ(rays.width, 1824);
  ASSERT_EQ(rays.height, 16);
  EXPECT_EQ(rays.size(), 1824u * 16u);
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = std::asin(rays.directions[rays.index(0, ring)].z()) * 180.0 / M_PI;
    EXPECT_NEAR(elevation, -15.0 + 2.0 * ring, 1e-4) << ring;  // VLP-16: 2 deg spacing
  }
  for (int col : {0, 456, 912, 1823}) {
    const Eigen::Vector3f d = rays.directions[rays.index(col, 8)];
    const double azimuth = std::atan2(d.y(), d.x());
    const double expected = -M_PI + col * 2.0 * M_PI / 1824.0;
    EXPECT_NEAR(std::remainder(azimuth - expected, 2.0 * M_PI), 0.0, 1e-5) << col;
  }
  EXPECT_FLOAT_EQ(rays.range_min, 0.4f);
}

TEST(ArbitraryRays, NormalisedAndChecked) {
  const SensorRays rays = makeRays({{2, 0, 0}, {0, 0, -3}});
  EXPECT_TRUE(rays.directions[1].isApprox(Eigen::Vector3f(0, 0, -1)));
  EXPECT_THROW(makeRays({{0, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(makeRays({{1, 0, 0}}, {{0, 0, 0}, {1, 1, 1}}), std::invalid_argument);
}

Eigen::Isometry3d cameraLookingAt(const Eigen::Vector3d& eye,
                                  const Eigen::Matrix3d& R_world_optical) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_world_optical;
  T.translation() = eye;
  return T;
}

TEST(Simulation, DepthOfATiltedPlaneIsAnalytic) {
  // A wall (thin box) at x = 3 facing -x; the camera at the origin looks along +x, rotated 20
  // deg about its optical axis and tilted: depth of each pixel = distance to the plane along z.
  RaycastScene scene;
  TriangleMesh wall = makeBox({0.02f, 40, 40});
  wall.transform(Eigen::Isometry3f(Eigen::Translation3f(3, 0, 0)));
  scene.setStaticMap(std::make_shared<TriangleMesh>(wall), 1);
  scene.commit();
  const Eigen::Matrix3d R_world_optical0 =
      (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
  const Eigen::Matrix3d R = R_world_optical0 * Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX());
  const Eigen::Isometry3d T = cameraLookingAt({0, 0.3, 1.2}, R);
  const PinholeModel cam;
  const SensorRays rays = makeRays(cam);
  const SimulatedScan scan = simulate(scene, rays, T);
  const std::vector<float> depth = depthImage(scan, rays);
  // Plane in the camera frame: n_c . p = d_c with n_c = R^T (1,0,0), d_c = 2.99 - n . eye.
  const Eigen::Vector3d n_c = R.transpose() * Eigen::Vector3d::UnitX();
  const double d_c = 2.99 - Eigen::Vector3d::UnitX().dot(T.translation());
  int checked = 0;
  for (int v = 0; v < cam.height; v += 7)
    for (int u = 0; u < cam.width; u += 7) {
      const std::size_t i = rays.index(u, v);
      ASSERT_EQ(scan.node[i], 1);
      const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      const double z = d_c / n_c.dot(ray);
      EXPECT_NEAR(depth[i], z, 2e-5 * z) << u << "," << v;
      EXPECT_TRUE(scan.normals[i].isApprox((-n_c).cast<float>(), 1e-5f));
      ++checked;
    }
  EXPECT_GT(checked, 6000);
}

TEST(Simulation, LidarSeesTheRoomAroundIt) {
  // Inside a 10 m cube-shaped room (inward faces of a box seen from inside), every ray hits and
  // the point lies on one of the six walls.
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({10, 10, 10})), 1);
  scene.commit();
  const SensorRays rays = makeRays(SpinningLidarModel::vlp16());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1, -2, 0.5);
  T.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const SimulatedScan scan = simulate(scene, rays, T);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(scan.node[i], 1);
    const Eigen::Vector3d p = T * scan.points[i].cast<double>();
    EXPECT_NEAR(p.cwiseAbs().maxCoeff(), 5.0, 1e-4);
  }
}

}  // namespace
}  // namespace sgt
