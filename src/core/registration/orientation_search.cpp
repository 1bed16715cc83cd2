#include "scene_graph_tracker/registration/orientation_search.hpp"

#include <algorithm>
#include <stdexcept>

namespace sgt {

std::vector<Eigen::Matrix3d> cuboidRotations() {
  std::vector<Eigen::Matrix3d> out{Eigen::Matrix3d::Identity()};
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
      for (int col = 0; col < 3; ++col) R(p[col], col) = (signs >> col) & 1 ? -1.0 : 1.0;
      if (R.determinant() > 0 && !R.isIdentity()) out.push_back(R);
    }
  return out;
}

std::vector<Eigen::Isometry3d> orientationCandidates(
    const Eigen::Isometry3d& T_world_object, const Eigen::AlignedBox3f& box,
    const std::vector<Eigen::Matrix3d>& rotations) {
  const Eigen::Vector3d c = box.center().cast<double>();
  std::vector<Eigen::Isometry3d> out;
  out.reserve(rotations.size());
  for (const Eigen::Matrix3d& R : rotations) {
    Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
    turn.linear() = R;
    turn.translation() = c - R * c;  // about the box centre
    out.push_back(T_world_object * turn);
  }
  return out;
}

OrientationChoice chooseOrientation(RaycastScene& scene, const RefineTarget& target,
                                    const std::vector<Eigen::Isometry3d>& candidates,
                                    const std::vector<RangeMeasurements>& measurements,
                                    const RefinerOptions& refiner, const OrientationPrior& prior) {
  if (candidates.empty()) throw std::invalid_argument("chooseOrientation: no candidates");
  OrientationChoice best;
  best.T_world_object = candidates.front();
  best.score = -1.0;
  const ObjectRefiner r(refiner);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    scene.setInstancePose(target.node, candidates[k]);
    scene.commit();
    const ObjectEstimate e = r.refine(scene, {target}, measurements).objects.front();
    if (e.quality.status == RefineStatus::kOk)
      ++best.candidates_fitted;
    else if (!prior.weak_fits_score)
      continue;
    // MSAC-style: each inlier counts 1 - (r / threshold)^2, so a closer fit of the same points
    // wins (an upside-down box explains nearly the same pixels, a few mm worse).
    const double fit = std::max(0.0, 1.0 - e.quality.rms_of_threshold * e.quality.rms_of_threshold);
    double score = e.quality.inliers * e.quality.inlier_ratio * fit;
    if (k > 0) score /= 1.0 + prior.own_margin;  // the detection's own orientation wins ties
    if (prior.world_up)
      score *= 1.0 + prior.upright_bonus *
                         std::max(0.0, e.T_world_object.linear().col(2).dot(*prior.world_up));
    if (score > best.score)
      best.candidate = k, best.T_world_object = e.T_world_object, best.quality = e.quality,
      best.score = score;
  }
  if (best.score < 0.0) best.score = 0.0;
  scene.setInstancePose(target.node, best.T_world_object);
  scene.commit();
  return best;
}

}  // namespace sgt
