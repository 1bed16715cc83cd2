// Cuboid PnP on synthetic projections: exact, noisy, with 4–5 points, too few, behind the camera.
#include <gtest/gtest.h>

#include <random>

#include "scene_graph_tracker/detection/cuboid_pnp.hpp"
#include "support.hpp"

using namespace sgt;
using namespace sgt::detection;

namespace {

const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-0.09, -0.044, -0.021),
                               Eigen::Vector3d(0.09, 0.044, 0.021));  // multimeter-ish

Eigen::Isometry3d truePose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1, -0.05, 0.9);
  return T;
}

std::vector<Keypoint> project(const Eigen::Isometry3d& T, const PinholeModel& cam,
                              double noise_px = 0.0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise_px);
  std::vector<Keypoint> kps;
  for (const auto& p : cuboidKeypoints(kBox)) {
    const Eigen::Vector3d q = T * p;
    Keypoint k;
    k.px = Eigen::Vector2d(cam.fx * q.x() / q.z() + cam.cx, cam.fy * q.y() / q.z() + cam.cy);
    if (noise_px > 0) k.px += Eigen::Vector2d(n(rng), n(rng));
    k.visibility = 0.9f;
    kps.push_back(k);
  }
  return kps;
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

}  // namespace

TEST(Cuboid, DopeOrder) {
  const auto k = cuboidKeypoints(kBox);
  EXPECT_TRUE(k[0].isApprox(Eigen::Vector3d(0.09, 0.044, 0.021)));     // front top right
  EXPECT_TRUE(k[1].isApprox(Eigen::Vector3d(-0.09, 0.044, 0.021)));    // front top left
  EXPECT_TRUE(k[2].isApprox(Eigen::Vector3d(-0.09, -0.044, 0.021)));   // front bottom left
  EXPECT_TRUE(k[3].isApprox(Eigen::Vector3d(0.09, -0.044, 0.021)));    // front bottom right
  EXPECT_TRUE(k[6].isApprox(Eigen::Vector3d(-0.09, -0.044, -0.021)));  // rear bottom left
  EXPECT_TRUE(k[8].isZero());
  // A model transform moves the corners into the object frame.
  Eigen::Isometry3d T_model_object = Eigen::Isometry3d::Identity();
  T_model_object.translation() = Eigen::Vector3d(0, 0, 0.5);
  EXPECT_TRUE(cuboidKeypoints(kBox, T_model_object)[8].isApprox(Eigen::Vector3d(0, 0, -0.5)));
}

TEST(CuboidPnp, ExactProjectionsGiveTheExactPose) {
  const PinholeModel cam;
  const auto r = solveCuboidPnp(project(truePose(), cam), cuboidKeypoints(kBox), cam);
  ASSERT_TRUE(r.ok()) << pnpStatusName(r.status);
  EXPECT_EQ(r.points_used, 9);
  EXPECT_LT(translationError(r.T_camera_object, truePose()), 1e-6);
  EXPECT_LT(test::rotationErrorDeg(r.T_camera_object.linear(), truePose().linear()), 1e-4);
  EXPECT_LT(r.reprojection_rms_px, 1e-6);
}

TEST(CuboidPnp, OnePixelNoiseStaysWithinCentimetres) {
  const PinholeModel cam;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const auto r = solveCuboidPnp(project(truePose(), cam, 1.0, seed), cuboidKeypoints(kBox), cam);
    ASSERT_TRUE(r.ok()) << pnpStatusName(r.status);
    EXPECT_LT(translationError(r.T_camera_object, truePose()), 0.03) << "seed " << seed;
    EXPECT_LT(test::rotationErrorDeg(r.T_camera_object.linear(), truePose().linear()), 5.0)
        << "seed " << seed;
    EXPECT_GT(r.reprojection_rms_px, 0.2);
    EXPECT_LT(r.reprojection_rms_px, 2.0);
  }
}

TEST(CuboidPnp, FourAndFivePointsUseP3PFamily) {
  const PinholeModel cam;
  for (int visible : {4, 5}) {
    auto kps = project(truePose(), cam);
    // Keep front top right, front top left, rear bottom left (+ centre): non-coplanar sets.
    const std::vector<int> keep =
        visible == 4 ? std::vector<int>{0, 1, 6, 8} : std::vector<int>{0, 1, 3, 6, 8};
    for (int k = 0; k < 9; ++k)
      if (std::find(keep.begin(), keep.end(), k) == keep.end()) kps[k].visibility = 0.1f;
    const auto r = solveCuboidPnp(kps, cuboidKeypoints(kBox), cam);
    ASSERT_TRUE(r.ok()) << visible << ": " << pnpStatusName(r.status);
    EXPECT_EQ(r.points_used, visible);
    EXPECT_LT(translationError(r.T_camera_object, truePose()), 1e-4) << visible;
    EXPECT_LT(test::rotationErrorDeg(r.T_camera_object.linear(), truePose().linear()), 0.05)
        << visible;
  }
}

TEST(CuboidPnp, ThreePointsOrOutsideTheImageGiveNoPose) {
  const PinholeModel cam;
  auto kps = project(truePose(), cam);
  for (int k = 3; k < 9; ++k) kps[k].visibility = 0.0f;
  auto r = solveCuboidPnp(kps, cuboidKeypoints(kBox), cam);
  EXPECT_EQ(r.status, PnpStatus::TooFewPoints);
  EXPECT_EQ(r.points_used, 3);
  kps = project(truePose(), cam);
  for (int k = 0; k < 6; ++k) kps[k].px = Eigen::Vector2d(-50, 10);  // outside the image
  r = solveCuboidPnp(kps, cuboidKeypoints(kBox), cam);
  EXPECT_EQ(r.status, PnpStatus::TooFewPoints);
  kps[6].px = Eigen::Vector2d(std::nan(""), 1);
  EXPECT_EQ(solveCuboidPnp(kps, cuboidKeypoints(kBox), cam).points_used, 2);
}

TEST(CuboidPnp, ObjectBehindTheCameraIsNeverAccepted) {
  // A box is point-symmetric, so the image of a box behind the camera is also nearly the image of
  // one in front; a tapered, off-centre point set is not, which leaves the solver only the
  // behind-the-camera fit (or a bad one in front) to choose from.
  auto points = cuboidKeypoints(kBox);
  for (int k = 4; k < 8; ++k) points[k].head<2>() *= 0.3;
  points[8] = Eigen::Vector3d(0.05, 0.02, 0.015);
  const PinholeModel cam;
  Eigen::Isometry3d behind = truePose();
  behind.translation().z() = -0.6;
  std::vector<Keypoint> kps;
  for (const auto& p : points) {
    const Eigen::Vector3d q = behind * p;
    kps.push_back(
        {Eigen::Vector2d(cam.fx * q.x() / q.z() + cam.cx, cam.fy * q.y() / q.z() + cam.cy), 1.0f});
  }
  PnpOptions opt;
  opt.max_reprojection_px = 3.0;
  const auto r = solveCuboidPnp(kps, points, cam, opt);
  EXPECT_FALSE(r.ok()) << "z = " << r.T_camera_object.translation().z() << ", rms "
                       << r.reprojection_rms_px;
  EXPECT_NE(r.status, PnpStatus::TooFewPoints);
  // The same points in front of the camera are solved exactly.
  Eigen::Isometry3d front = behind;
  front.translation().z() = 0.6;
  kps.clear();
  for (const auto& p : points) {
    const Eigen::Vector3d q = front * p;
    kps.push_back(
        {Eigen::Vector2d(cam.fx * q.x() / q.z() + cam.cx, cam.fy * q.y() / q.z() + cam.cy), 1.0f});
  }
  const auto f = solveCuboidPnp(kps, points, cam, opt);
  ASSERT_TRUE(f.ok()) << pnpStatusName(f.status);
  EXPECT_LT(translationError(f.T_camera_object, front), 1e-5);
}

TEST(CuboidPnp, ScrambledKeypointsGiveALargeReprojectionError) {
  const PinholeModel cam;
  auto kps = project(truePose(), cam);
  std::swap(kps[0].px, kps[6].px);
  std::swap(kps[1].px, kps[7].px);
  std::swap(kps[2].px, kps[4].px);
  PnpOptions opt;
  opt.max_reprojection_px = 2.0;
  const auto r = solveCuboidPnp(kps, cuboidKeypoints(kBox), cam, opt);
  EXPECT_FALSE(r.ok());
}
