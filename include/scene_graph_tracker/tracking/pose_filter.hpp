// Kalman filter on an object's pose: constant linear and angular velocity, orientation kept as a
// rotation matrix with a 3-vector error state (error-state / multiplicative EKF), so the filter
// never meets the singularities of Euler angles. State error [dp, dv, dtheta, dw] (12), world
// frame, dtheta perturbing the rotation on the left: R_true = Exp(dtheta) R.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "scene_graph_tracker/scene/object_catalog.hpp"

namespace sgt {

struct PoseFilterNoise {
  double accel = 0.2;          // m/s^2, white-noise acceleration (a hand moving an object)
  double angular_accel = 0.2;  // rad/s^2 (higher makes the turn rate follow pose noise)
  double initial_velocity = 0.2, initial_angular_velocity = 0.5;  // 1 sigma of the unknown start
  // While a track coasts (no measurement), its velocities decay with this time constant: an
  // object put down stops; carrying on at the last velocity would fly it away in a second. Short,
  // because a far object's velocity is mostly refinement jitter, which a longer decay carries a
  // hidden object away on.
  double coast_decay_s = 0.05;
  // Manoeuvres (an object picked up, carried, turned in a hand) break the constant-velocity
  // model. A measurement whose translation or rotation innovation the model cannot explain
  // (normalized innovation squared beyond the 99 % chi-square bound of its 3 degrees of freedom)
  // multiplies that part's process noise by this factor for the following predictions; each
  // measurement that fits halves the factor back towards 1. 1: off.
  double max_noise_scale = 1.0;
};

class PoseFilter {
 public:
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;

  PoseFilter(const Eigen::Isometry3d& T, const Mat6& pose_covariance,
             const PoseFilterNoise& noise = {});

  void predict(double dt);
  // Lets the velocities decay over `dt` (see PoseFilterNoise::coast_decay_s); for coasting.
  void damp(double dt);
  // A measured pose with its covariance ([translation, rotation] in the world frame). With a
  // symmetry, the symmetric twin of the measurement closest to the prediction is used, so a
  // crate seen turned by 180 deg does not spin the filter. Returns the squared Mahalanobis
  // distance of the innovation.
  double update(const Eigen::Isometry3d& T_measured, const Mat6& covariance,
                const Symmetry* symmetry = nullptr);
  // Squared Mahalanobis distance of a pose from the prediction, without updating.
  double distance2(const Eigen::Isometry3d& T, const Mat6& covariance,
                   const Symmetry* symmetry = nullptr) const;
  // The same for the rotation alone (3 degrees of freedom); `covariance` is the measurement's
  // full 6x6 one, of which its rotation block counts.
  double turnDistance2(const Eigen::Isometry3d& T, const Mat6& covariance,
                       const Symmetry* symmetry = nullptr) const;
  // The same for the position alone (3 degrees of freedom; its translation block counts).
  double shiftDistance2(const Eigen::Isometry3d& T, const Mat6& covariance) const;

  Eigen::Isometry3d pose() const;
  const Eigen::Vector3d& velocity() const { return v_; }
  const Eigen::Vector3d& angularVelocity() const { return w_; }
  const Mat12& covariance() const { return P_; }
  // The current process-noise scales (>= 1) of translation and rotation (max_noise_scale).
  double translationNoiseScale() const { return scale_t_; }
  double rotationNoiseScale() const { return scale_r_; }
  Mat6 poseCovariance() const;

 private:
  Eigen::Matrix<double, 6, 1> innovation(const Eigen::Isometry3d& T_measured,
                                         const Symmetry* symmetry) const;
  void adaptNoise(const Eigen::Matrix<double, 6, 1>& r, const Mat6& S);

  Eigen::Vector3d p_, v_ = Eigen::Vector3d::Zero(), w_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_;
  Mat12 P_;
  PoseFilterNoise noise_;
  double scale_t_ = 1.0, scale_r_ = 1.0;
};

// Covariance of a pose measurement with independent noise: sigma_m (m) on each translation
// axis, sigma_rad on each rotation axis ([t, R] order).
PoseFilter::Mat6 diagonalCovariance(double sigma_m, double sigma_rad);

// Covariance of a fitted pose ([translation, rotation] in the world frame) from the information
// of its point-to-plane terms (sum of J J^T, ObjectQuality::information) and the noise of one
// point along its normal: small where many rays pin the pose down, large in the directions they
// leave free (at most about 1 m and 1 rad, where no ray constrains it). Rotations about
// `free_axes` (world, unit: continuous symmetry axes) are not the fit's to find and add nothing.
PoseFilter::Mat6 fitCovariance(const PoseFilter::Mat6& information, double point_sigma_m,
                               const std::vector<Eigen::Vector3d>& free_axes = {});

// Whether `C` is less certain than `reference` in some direction: the largest eigenvalue of
// reference^-1/2 C reference^-1/2 (reference diagonal) exceeds 1.
bool looserThan(const PoseFilter::Mat6& C, const PoseFilter::Mat6& reference);

// Rotation vector of R (log map) and its inverse.
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R);
Eigen::Matrix3d expSO3(const Eigen::Vector3d& w);

}  // namespace sgt
