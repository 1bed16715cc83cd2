#include "scene_graph_tracker/detection/keypoint_labels.hpp"

namespace sgt::detection {

Eigen::Matrix3d canonicalLabelRotation() { return Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(); }

namespace {

// Among T * S * B the one whose rotation is closest to the canonical one (the first on ties).
Eigen::Isometry3d closestToCanonical(const Eigen::Isometry3d& T_camera_object,
                                     const std::vector<Eigen::Isometry3d>& symmetries,
                                     const std::vector<Eigen::Isometry3d>& turns) {
  // The geodesic angle falls as trace(Rc^T R) grows.
  const Eigen::Matrix3d Rc_t = canonicalLabelRotation().transpose();
  Eigen::Isometry3d best = T_camera_object;
  double best_trace = -4.0;
  for (const Eigen::Isometry3d& S : symmetries)
    for (const Eigen::Isometry3d& B : turns) {
      const Eigen::Isometry3d T = T_camera_object * S * B;
      const double trace = (Rc_t * T.linear()).trace();
      if (trace > best_trace) best_trace = trace, best = T;
    }
  return best;
}

}  // namespace

Eigen::Isometry3d canonicalSymmetricPose(const Eigen::Isometry3d& T_camera_object,
                                         const Symmetry& symmetry, double continuous_step_rad) {
  if (!symmetry.any()) return T_camera_object;
  return closestToCanonical(T_camera_object, symmetry.sampled(continuous_step_rad),
                            {Eigen::Isometry3d::Identity()});
}

std::array<Eigen::Isometry3d, 4> boxHalfTurns() {
  return sgt::boxHalfTurns(Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()));
}

Eigen::Isometry3d canonicalCuboidPose(const Eigen::Isometry3d& T_camera_object,
                                      const Symmetry& symmetry, double continuous_step_rad) {
  const auto turns = boxHalfTurns();
  return closestToCanonical(T_camera_object, symmetry.sampled(continuous_step_rad),
                            {turns.begin(), turns.end()});
}

CuboidProjection projectCuboid(const PinholeModel& camera, const Eigen::Isometry3d& T_camera_object,
                               const Eigen::AlignedBox3d& box) {
  CuboidProjection out;
  const auto corners = cuboidKeypoints(box);
  for (int k = 0; k < kCuboidKeypoints; ++k) {
    out.uv[k].setZero();
    const auto uv = camera.project(T_camera_object * corners[k]);
    // Pixel centres sit at integer coordinates (CameraInfo's convention): the image spans -0.5 .. W
    // - 0.5.
    if (!uv || uv->x() < -0.5 || uv->y() < -0.5 || uv->x() >= camera.width - 0.5 ||
        uv->y() >= camera.height - 0.5)
      continue;
    out.uv[k] = *uv;
    out.inside[k] = true;
  }
  return out;
}

}  // namespace sgt::detection
