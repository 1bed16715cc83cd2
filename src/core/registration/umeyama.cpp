#include "scene_graph_tracker/registration/umeyama.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace sgt {

const char* toString(AlignmentStatus s) {
  switch (s) {
    case AlignmentStatus::kOk:
      return "ok";
    case AlignmentStatus::kTooFewPoints:
      return "too few points";
    case AlignmentStatus::kCollinear:
      return "collinear points";
    case AlignmentStatus::kPlanar:
      return "planar points";
  }
  return "?";
}

Alignment umeyama(const PairMoments& m, const AlignmentOptions& options) {
  Alignment out;
  if (m.n < std::max(3, options.min_points)) return out;
  const Eigen::Vector3d mu_a = m.sum_a / m.n, mu_b = m.sum_b / m.n;
  const Eigen::Matrix3d cov_aa = m.sum_aa / m.n - mu_a * mu_a.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov_aa, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
  if (!(lambda(2) > 0.0) || lambda(1) < options.collinear_ratio * lambda(2)) {
    out.status = AlignmentStatus::kCollinear;
    return out;
  }
  if (options.reject_planar && lambda(0) < options.planar_ratio * lambda(2)) {
    out.status = AlignmentStatus::kPlanar;
    return out;
  }
  const Eigen::Matrix3d cov_ba = m.sum_ba / m.n - mu_b * mu_a.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov_ba, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;
  out.T.linear() = svd.matrixU() * S * svd.matrixV().transpose();
  out.T.translation() = mu_b - out.T.linear() * mu_a;
  out.status = AlignmentStatus::kOk;
  return out;
}

}  // namespace sgt
