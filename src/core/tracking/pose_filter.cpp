#include "scene_graph_tracker/tracking/pose_filter.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sgt {

Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w) {
  const double a = w.norm();
  return a < 1e-12 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

PoseFilter::PoseFilter(const Eigen::Isometry3d& T, const Mat6& cov, const PoseFilterNoise& noise)
    : p_(T.translation()), R_(T.linear()), noise_(noise) {
  P_.setZero();
  P_.block<3, 3>(0, 0) = cov.block<3, 3>(0, 0);
  P_.block<3, 3>(6, 6) = cov.block<3, 3>(3, 3);
  P_.block<3, 3>(0, 6) = cov.block<3, 3>(0, 3);
  P_.block<3, 3>(6, 0) = cov.block<3, 3>(3, 0);
  P_.block<3, 3>(3, 3) =
      Eigen::Matrix3d::Identity() * noise.initial_velocity * noise.initial_velocity;
  P_.block<3, 3>(9, 9) =
      Eigen::Matrix3d::Identity() * noise.initial_angular_velocity * noise.initial_angular_velocity;
}

void PoseFilter::predict(double dt) {
  if (!(dt > 0.0)) return;
  p_ += v_ * dt;
  R_ = expSO3(w_ * dt) * R_;
  Mat12 F = Mat12::Identity();
  F.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity() * dt;
  F.block<3, 3>(6, 9) = Eigen::Matrix3d::Identity() * dt;
  Mat12 Q = Mat12::Zero();
  const auto block = [&](int i, double sigma) {  // white-noise acceleration on (x, dx/dt)
    const double q = sigma * sigma;
    Q.block<3, 3>(i, i) = Eigen::Matrix3d::Identity() * q * dt * dt * dt / 3.0;
    Q.block<3, 3>(i, i + 3) = Q.block<3, 3>(i + 3, i) =
        Eigen::Matrix3d::Identity() * q * dt * dt / 2.0;
    Q.block<3, 3>(i + 3, i + 3) = Eigen::Matrix3d::Identity() * q * dt;
  };
  block(0, noise_.accel * std::sqrt(scale_t_));
  block(6, noise_.angular_accel * std::sqrt(scale_r_));
  P_ = F * P_ * F.transpose() + Q;
}

void PoseFilter::damp(double dt) {
  if (!(dt > 0.0) || !(noise_.coast_decay_s > 0.0)) return;
  const double k = std::exp(-dt / noise_.coast_decay_s);
  v_ *= k, w_ *= k;
  Mat12 D = Mat12::Identity();
  D.block<3, 3>(3, 3) *= k;
  D.block<3, 3>(9, 9) *= k;
  P_ = D * P_ * D.transpose();
}

Eigen::Matrix<double, 6, 1> PoseFilter::innovation(const Eigen::Isometry3d& T,
                                                   const Symmetry* symmetry) const {
  Eigen::Matrix<double, 6, 1> r;
  r.head<3>() = T.translation() - p_;
  r.tail<3>() = logSO3(T.linear() * R_.transpose());
  if (symmetry && symmetry->any()) {  // the twin of T closest in rotation to the prediction
    double best = r.tail<3>().squaredNorm();
    for (const Eigen::Isometry3d& S : symmetry->sampled(M_PI / 90.0)) {
      const Eigen::Isometry3d twin = T * S.inverse();
      const Eigen::Vector3d dr = logSO3(twin.linear() * R_.transpose());
      if (dr.squaredNorm() < best)
        best = dr.squaredNorm(), r.head<3>() = twin.translation() - p_, r.tail<3>() = dr;
    }
  }
  return r;
}

double PoseFilter::distance2(const Eigen::Isometry3d& T, const Mat6& cov,
                             const Symmetry* symmetry) const {
  const Eigen::Matrix<double, 6, 1> r = innovation(T, symmetry);
  return r.dot((poseCovariance() + cov).ldlt().solve(r));
}

double PoseFilter::turnDistance2(const Eigen::Isometry3d& T, const Mat6& cov,
                                 const Symmetry* symmetry) const {
  const Eigen::Vector3d r = innovation(T, symmetry).tail<3>();
  const Eigen::Matrix3d S = P_.block<3, 3>(6, 6) + cov.bottomRightCorner<3, 3>();
  return r.dot(S.ldlt().solve(r));
}

double PoseFilter::shiftDistance2(const Eigen::Isometry3d& T, const Mat6& cov) const {
  const Eigen::Vector3d r = T.translation() - p_;
  const Eigen::Matrix3d S = P_.block<3, 3>(0, 0) + cov.topLeftCorner<3, 3>();
  return r.dot(S.ldlt().solve(r));
}

double PoseFilter::update(const Eigen::Isometry3d& T, const Mat6& cov, const Symmetry* symmetry) {
  const Eigen::Matrix<double, 6, 1> r = innovation(T, symmetry);
  Eigen::Matrix<double, 6, 12> H = Eigen::Matrix<double, 6, 12>::Zero();
  H.block<3, 3>(0, 0).setIdentity();
  H.block<3, 3>(3, 6).setIdentity();
  const Mat6 S = H * P_ * H.transpose() + cov;
  adaptNoise(r, S);
  const Eigen::Matrix<double, 12, 6> K = P_ * H.transpose() * S.inverse();
  const Eigen::Matrix<double, 12, 1> dx = K * r;
  p_ += dx.segment<3>(0);
  v_ += dx.segment<3>(3);
  R_ = expSO3(dx.segment<3>(6)) * R_;
  w_ += dx.segment<3>(9);
  const Mat12 I_KH = Mat12::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * cov * K.transpose();  // Joseph form: stays symmetric PSD
  return r.dot(S.ldlt().solve(r));
}

void PoseFilter::adaptNoise(const Eigen::Matrix<double, 6, 1>& r, const Mat6& S) {
  if (!(noise_.max_noise_scale > 1.0)) return;
  constexpr double kChi2_3_99 = 11.345;  // 99 % quantile of chi-square with 3 dof
  const auto adapt = [&](double& scale, int i) {
    const double nis = r.segment<3>(i).dot(S.block<3, 3>(i, i).ldlt().solve(r.segment<3>(i)));
    scale = nis > kChi2_3_99 ? noise_.max_noise_scale : std::max(1.0, 0.5 * scale);
  };
  adapt(scale_t_, 0);
  adapt(scale_r_, 3);
}

Eigen::Isometry3d PoseFilter::pose() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R_).normalized().toRotationMatrix();
  T.translation() = p_;
  return T;
}

PoseFilter::Mat6 PoseFilter::poseCovariance() const {
  Mat6 C;
  C.block<3, 3>(0, 0) = P_.block<3, 3>(0, 0);
  C.block<3, 3>(0, 3) = P_.block<3, 3>(0, 6);
  C.block<3, 3>(3, 0) = P_.block<3, 3>(6, 0);
  C.block<3, 3>(3, 3) = P_.block<3, 3>(6, 6);
  return C;
}

PoseFilter::Mat6 diagonalCovariance(double sigma_m, double sigma_rad) {
  PoseFilter::Mat6 C = PoseFilter::Mat6::Zero();
  C.diagonal() << Eigen::Vector3d::Constant(sigma_m * sigma_m),
      Eigen::Vector3d::Constant(sigma_rad * sigma_rad);
  return C;
}

PoseFilter::Mat6 fitCovariance(const PoseFilter::Mat6& information, double point_sigma_m,
                               const std::vector<Eigen::Vector3d>& free_axes) {
  // A unit prior (1 m, 1 rad) keeps unconstrained directions finite.
  PoseFilter::Mat6 I = information / (point_sigma_m * point_sigma_m);
  I += PoseFilter::Mat6::Identity();
  // A symmetry axis: the rotation about it is as certain as any, since no turn about it matters.
  const double known = I.bottomRightCorner<3, 3>().trace() + 1.0;
  for (const Eigen::Vector3d& a : free_axes)
    I.bottomRightCorner<3, 3>() += known * a * a.transpose();
  return I.ldlt().solve(PoseFilter::Mat6::Identity());
}

bool looserThan(const PoseFilter::Mat6& C, const PoseFilter::Mat6& reference) {
  const Eigen::Matrix<double, 6, 1> s = reference.diagonal().cwiseSqrt().cwiseInverse();
  const PoseFilter::Mat6 scaled = s.asDiagonal() * C * s.asDiagonal();
  return Eigen::SelfAdjointEigenSolver<PoseFilter::Mat6>(scaled, Eigen::EigenvaluesOnly)
             .eigenvalues()
             .maxCoeff() > 1.0;
}

}  // namespace sgt
