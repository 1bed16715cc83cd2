// Keeping composed rigid transforms rigid.
//
// Eigen::Isometry3d::inverse() transposes the rotation block, which is only the inverse for an
// orthonormal matrix. A pose that is corrected every frame by `estimate * prior.inverse() * pose`
// (the map -> odom correction) amplifies any deviation from orthonormality about threefold per
// correction: from rounding noise (1e-16) to a 0.6 % shear of the scans within ~30 corrections,
// which held the localizer's threshold open and let it drift (issue 5). Every pose that is stored
// across frames goes through rigid() after it is composed.
#pragma once

#include <Eigen/Geometry>

namespace sgt {

// The nearest rigid transform (rotation re-orthonormalised through its quaternion).
inline Eigen::Isometry3d rigid(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  out.translation() = T.translation();
  return out;
}

// || R^T R - I ||_F: 0 for a rotation.
inline double orthonormalityError(const Eigen::Isometry3d& T) {
  return (T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm();
}

}  // namespace sgt
