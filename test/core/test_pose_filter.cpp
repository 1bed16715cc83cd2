// The pose Kalman filter: learns a constant motion from noisy poses, coasts through a gap,
// accepts a crate's symmetric twin without spinning, and gates by Mahalanobis distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "scene_graph_tracker/tracking/pose_filter.hpp"
#include "support.hpp"

namespace sgt {
namespace {

Eigen::Isometry3d truthAt(double t) {  // 0.2 m/s along x, 0.5 rad/s about z
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1.0 + 0.2 * t, 2.0, 0.8);
  T.linear() = Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

PoseFilter::Mat6 covariance(double sigma_t, double sigma_r) {
  PoseFilter::Mat6 C = PoseFilter::Mat6::Zero();
  C.diagonal() << Eigen::Vector3d::Constant(sigma_t * sigma_t),
      Eigen::Vector3d::Constant(sigma_r * sigma_r);
  return C;
}

TEST(PoseFilter, LearnsAConstantMotionAndCoastsThroughAGap) {
  std::mt19937 rng(2);
  std::normal_distribution<double> g;
  // 2 s of refined poses at 30 Hz with 1 mm / 0.2 deg noise (what refinement leaves).
  const PoseFilter::Mat6 C = covariance(0.001, 0.0035);
  PoseFilter f(truthAt(0), C);
  const double dt = 1.0 / 30.0;
  for (int k = 1; k <= 60; ++k) {
    f.predict(dt);
    Eigen::Isometry3d m = truthAt(k * dt);
    m.translation() += 0.001 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    m.linear() = expSO3(0.0035 * Eigen::Vector3d(g(rng), g(rng), g(rng))) * m.linear();
    f.update(m, C);
  }
  EXPECT_NEAR(f.velocity().x(), 0.2, 0.02);
  EXPECT_NEAR(f.angularVelocity().z(), 0.5, 0.05);
  // One second without measurements: the prediction follows the motion (20 cm, 29 deg) closely.
  for (int k = 61; k <= 90; ++k) f.predict(dt);
  const Eigen::Isometry3d truth = truthAt(90 * dt);
  EXPECT_LT((f.pose().translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(test::rotationErrorDeg(f.pose().linear(), truth.linear()), 5.0);
  // ... and its uncertainty grew meanwhile.
  EXPECT_GT(f.poseCovariance()(0, 0), C(0, 0));
}

TEST(PoseFilter, CoastingSlowsDown) {
  const PoseFilter::Mat6 C = covariance(0.001, 0.0035);
  PoseFilter f(truthAt(0), C);
  for (int k = 1; k <= 60; ++k) f.predict(1.0 / 30.0), f.update(truthAt(k / 30.0), C);
  ASSERT_NEAR(f.velocity().x(), 0.2, 0.02);
  const Eigen::Vector3d before = f.pose().translation();
  for (int k = 0; k < 60; ++k) f.damp(1.0 / 30.0), f.predict(1.0 / 30.0);  // 2 s coasting
  // With decay constant 0.3 s the object travels at most 0.2 m/s x 0.3 s = 6 cm, not 40 cm.
  EXPECT_LT((f.pose().translation() - before).norm(), 0.065);
  EXPECT_LT(f.velocity().norm(), 0.001);
}

// An object at rest for 1 s, then picked up: 0.8 m/s and 2.5 rad/s from one frame to the next,
// measured at 30 Hz with 2 mm / 0.01 rad noise.
struct PickUp {
  double translation_mm = 0.0, rotation_deg = 0.0;  // mean one-step prediction errors, first 0.5 s
  double rest_scale = 1.0;  // the largest noise scale while the object rested
};

PickUp pickUp(double max_noise_scale) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  PoseFilterNoise noise;
  noise.max_noise_scale = max_noise_scale;
  const PoseFilter::Mat6 C = covariance(0.002, 0.01);
  const auto truth = [](double t) {
    const double moving = std::max(0.0, t - 1.0);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(1.0 + 0.8 * moving, 2.0, 0.8);
    T.linear() = Eigen::AngleAxisd(2.5 * moving, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
  };
  PoseFilter f(truth(0), C, noise);
  const double dt = 1.0 / 30.0;
  PickUp out;
  for (int k = 1; k <= 45; ++k) {
    f.predict(dt);
    const Eigen::Isometry3d T = truth(k * dt);
    if (k > 30) {
      out.translation_mm += 1000.0 * (f.pose().translation() - T.translation()).norm() / 15.0;
      out.rotation_deg += test::rotationErrorDeg(f.pose().linear(), T.linear()) / 15.0;
    }
    Eigen::Isometry3d m = T;
    m.translation() += 0.002 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    m.linear() = expSO3(0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng))) * m.linear();
    f.update(m, C);
    if (k < 30)
      out.rest_scale =
          std::max({out.rest_scale, f.translationNoiseScale(), f.rotationNoiseScale()});
  }
  return out;
}

TEST(PoseFilter, AManoeuvreRaisesTheProcessNoiseUntilTheModelFollows) {
  const PickUp fixed = pickUp(1.0), adapted = pickUp(100.0);
  EXPECT_EQ(fixed.rest_scale, 1.0);
  EXPECT_LT(adapted.rest_scale, 5.0) << "noise at rest barely raises the process noise";
  EXPECT_LT(adapted.rotation_deg, 0.6 * fixed.rotation_deg)
      << "turn lag " << adapted.rotation_deg << " deg adapted, " << fixed.rotation_deg << " fixed";
  EXPECT_LT(adapted.translation_mm, 1.1 * fixed.translation_mm)
      << "translation lag " << adapted.translation_mm << " mm adapted, " << fixed.translation_mm
      << " fixed";
}

TEST(PoseFilter, SymmetricTwinDoesNotSpinTheFilter) {
  Symmetry half_turn;
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  half_turn.discrete.push_back(S);
  const PoseFilter::Mat6 C = covariance(0.002, 0.01);
  PoseFilter with(truthAt(0), C), without(truthAt(0), C);
  const Eigen::Isometry3d twin = truthAt(0) * S;  // looks the same
  EXPECT_LT(with.update(twin, C, &half_turn), 1e-6);
  EXPECT_LT(test::rotationErrorDeg(with.pose().linear(), truthAt(0).linear()), 1e-6);
  EXPECT_GT(without.update(twin, C), 1000.0);  // without the symmetry it is a huge innovation
}

TEST(PoseFilter, MahalanobisDistanceGates) {
  const PoseFilter::Mat6 C = covariance(0.01, 0.05);
  PoseFilter f(truthAt(0), C);
  Eigen::Isometry3d near = truthAt(0), far = truthAt(0);
  near.translation().x() += 0.01;
  far.translation().x() += 0.3;
  EXPECT_LT(f.distance2(near, C), 1.0);
  EXPECT_GT(f.distance2(far, C), 100.0);
}

TEST(PoseFilter, TurnDistanceWeighsTheRotationAloneAndForgivesSymmetricTwins) {
  const PoseFilter::Mat6 C = covariance(0.002, 0.01);
  PoseFilter f(truthAt(0), C);
  Eigen::Isometry3d moved = truthAt(0), tipped = truthAt(0), twin = truthAt(0);
  moved.translation().x() += 0.3;  // far, but not turned
  tipped.linear() = tipped.linear() * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX());
  EXPECT_LT(f.turnDistance2(moved, C), 1e-9);
  EXPECT_GT(f.distance2(moved, C), 1000.0);
  // 0.5 rad against sqrt(0.01^2 + 0.01^2) rad: (0.5 / 0.01414)^2 = 1250.
  EXPECT_NEAR(f.turnDistance2(tipped, C), 1250.0, 1.0);
  Symmetry half_turn;
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  half_turn.discrete.push_back(S);
  twin = truthAt(0) * S;
  EXPECT_LT(f.turnDistance2(twin, C, &half_turn), 1e-6);
  EXPECT_GT(f.turnDistance2(twin, C), 1000.0);
}

// Information (sum of J J^T, as the refiner sums it) of point-to-plane terms at `points` with
// `normal`, about `centre`.
PoseFilter::Mat6 planeInformation(const std::vector<Eigen::Vector3d>& points,
                                  const Eigen::Vector3d& normal, const Eigen::Vector3d& centre) {
  PoseFilter::Mat6 H = PoseFilter::Mat6::Zero();
  for (const Eigen::Vector3d& p : points) {
    Eigen::Matrix<double, 6, 1> J;
    J << normal, (p - centre).cross(normal);
    H += J * J.transpose();
  }
  return H;
}

// (2 half + 1)^2 points `spacing` apart on the top face of a 6 cm box centred at the origin: what
// a fit from above sees.
std::vector<Eigen::Vector3d> topFace(int half = 2, double spacing = 0.012) {
  std::vector<Eigen::Vector3d> points;
  for (int i = -half; i <= half; ++i)
    for (int j = -half; j <= half; ++j) points.emplace_back(spacing * i, spacing * j, 0.03);
  return points;
}

TEST(FitCovariance, ATopFaceLeavesItsOwnPlaneFree) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const PoseFilter::Mat6 H = planeInformation(topFace(), up, Eigen::Vector3d::Zero());
  const PoseFilter::Mat6 C = fitCovariance(H, 0.002);
  const Eigen::Matrix<double, 6, 1> sigma = C.diagonal().cwiseSqrt();
  EXPECT_LT(sigma(2), 0.001);                       // height: 25 points of 2 mm
  EXPECT_LT(sigma.segment<2>(3).maxCoeff(), 0.05);  // tilt about x and y: the face's spread
  EXPECT_GT(sigma.head<2>().minCoeff(), 0.5);       // sliding in the plane: nothing sees it
  EXPECT_GT(sigma(5), 0.5);                         // turning about the normal: nor that
  const PoseFilter::Mat6 refined = diagonalCovariance(0.002, 0.01);
  EXPECT_TRUE(looserThan(C, refined));
  // A symmetry about the normal: the turn about it is no longer asked of the fit.
  const PoseFilter::Mat6 Cs = fitCovariance(H, 0.002, {up});
  EXPECT_LT(std::sqrt(Cs(5, 5)), sigma.segment<2>(3).minCoeff());  // as sure as the tilts
  EXPECT_GT(std::sqrt(Cs(0, 0)), 0.5);
}

TEST(FitCovariance, AllSixFacesPinThePoseDown) {
  PoseFilter::Mat6 H = PoseFilter::Mat6::Zero();
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // takes z onto this face's normal
      if (axis == 0) R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
      if (axis == 1) R = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
      std::vector<Eigen::Vector3d> face;
      for (const Eigen::Vector3d& p : topFace(5, 0.005)) face.push_back(sign * (R * p));
      H += planeInformation(face, sign * (R * Eigen::Vector3d::UnitZ()), Eigen::Vector3d::Zero());
    }
  const PoseFilter::Mat6 C = fitCovariance(H, 0.002);
  EXPECT_LT(C.diagonal().head<3>().cwiseSqrt().maxCoeff(), 0.001);
  EXPECT_LT(C.diagonal().tail<3>().cwiseSqrt().maxCoeff(), 0.01);
  EXPECT_FALSE(looserThan(C, diagonalCovariance(0.002, 0.01)));
}

}  // namespace
}  // namespace sgt
