// Rigid alignment of point pairs (Umeyama 1991, no scale) from mergeable moments, so that pairs
// can be accumulated in parallel and reduced.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <optional>

namespace sgt {

// Sums over pairs (a = model point, b = measured point).
struct PairMoments {
  double n = 0.0;
  Eigen::Vector3d sum_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_ba = Eigen::Matrix3d::Zero();  // sum of b a^T
  Eigen::Matrix3d sum_aa = Eigen::Matrix3d::Zero();  // sum of a a^T (shape of the model side)
  double sum_sq = 0.0;                               // sum of |b - a|^2

  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    n += 1.0;
    sum_a += a;
    sum_b += b;
    sum_ba.noalias() += b * a.transpose();
    sum_aa.noalias() += a * a.transpose();
    sum_sq += (b - a).squaredNorm();
  }
  PairMoments& operator+=(const PairMoments& o) {
    n += o.n, sum_a += o.sum_a, sum_b += o.sum_b, sum_ba += o.sum_ba, sum_aa += o.sum_aa,
        sum_sq += o.sum_sq;
    return *this;
  }
  double rmse() const { return n > 0 ? std::sqrt(sum_sq / n) : 0.0; }
};

enum class AlignmentStatus { kOk, kTooFewPoints, kCollinear, kPlanar };
const char* toString(AlignmentStatus s);

struct AlignmentOptions {
  int min_points = 12;
  // Ratio of the smallest to the largest spread (eigenvalues of the model points' covariance)
  // under which the set counts as planar, and of the middle one as collinear.
  double planar_ratio = 1e-4;
  double collinear_ratio = 1e-4;
  bool reject_planar = true;
  // Degrees of freedom the linear point-to-plane step may change, in the frame the points are
  // given in: rotation about x, y, z, then translation along x, y, z. A ground robot localizes
  // in x, y and yaw only (its height, roll and pitch come from the floor it stands on).
  std::array<bool, 6> free_dofs{true, true, true, true, true, true};
};

struct Alignment {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // minimises sum |T a - b|^2
  AlignmentStatus status = AlignmentStatus::kTooFewPoints;
  bool ok() const { return status == AlignmentStatus::kOk; }
};

// Umeyama with the reflection fix (S33 = -1 when det(U) det(V) < 0).
Alignment umeyama(const PairMoments& m, const AlignmentOptions& options = {});

}  // namespace sgt
