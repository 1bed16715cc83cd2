// Pose error metrics with BOP's conventions (reference.md): ADD, ADD-S, symmetry-aware
// translation and rotation errors, and recall at 10 % of the object's diameter.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "scene_graph_tracker/scene/object_catalog.hpp"

namespace sgt {

// Mean distance between the model points under the estimated and the true pose.
double addError(const std::vector<Eigen::Vector3f>& model_points, const Eigen::Isometry3d& T_est,
                const Eigen::Isometry3d& T_true);
// Mean distance from each model point under the estimate to the closest model point under the
// truth (brute force: keep model_points to a few hundred).
double addSError(const std::vector<Eigen::Vector3f>& model_points, const Eigen::Isometry3d& T_est,
                 const Eigen::Isometry3d& T_true);

struct PoseErrors {
  double add = 0.0;    // ADD, minimised over the symmetries (BOP's ADD for symmetric objects is ADD-S)
  double add_s = 0.0;  // ADD-S: the sampled ADD-S, or `add` when that is smaller (see poseErrors)
  double translation = 0.0;   // |t_est - t_true| (m)
  double rotation_deg = 0.0;  // smallest angle between R_est and R_true S over the symmetries S
  bool correct = false;       // ADD-S < 10 % of the diameter (BOP recall criterion)
};

// Everything for one estimate of an object of class `object` (its mesh sampled with
// `model_points`, e.g. 500 area-uniform surface points).
PoseErrors poseErrors(const ObjectClass& object, const std::vector<Eigen::Vector3f>& model_points,
                      const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_true);

}  // namespace sgt
