// Which orientation of a newly detected object do the measurements support?
//
// A keypoint detector that confuses the corners of an object's box gives PnP a rotation that is
// off by one of the box's 24 axis permutations (the shipped model turns the material box by 90
// deg, the multimeter by 180 deg), and refinement, a local search, keeps that error for good:
// the rotated box explains part of the points well enough. When a track is confirmed (or a lost
// one restarts from a detection), each candidate orientation (its current one first) is refined
// briefly on its own, and the one whose surface explains most of what the sensors see wins.
#pragma once

#include <optional>
#include <vector>

#include "scene_graph_tracker/registration/object_refiner.hpp"

namespace sgt {

// The 24 rotations that map the axis-aligned cube onto itself (signed permutation matrices with
// determinant +1), identity first.
std::vector<Eigen::Matrix3d> cuboidRotations();

// T_world_object turned by each of `rotations` about the centre of `box` (object frame):
// the detection's box stays where it was seen.
std::vector<Eigen::Isometry3d> orientationCandidates(const Eigen::Isometry3d& T_world_object,
                                                     const Eigen::AlignedBox3f& box,
                                                     const std::vector<Eigen::Matrix3d>& rotations);

struct OrientationChoice {
  std::size_t candidate = 0;  // index into the candidates; 0 when none fits
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();  // refined
  ObjectQuality quality;
  double score = 0.0;  // the winner's score (see chooseOrientation)
  int candidates_fitted = 0;
};

// Refines `target` from every candidate pose with `refiner` (a few rounds suffice) against the
// measurements, every other instance of `scene` in place (occlusion as in refinement), and
// leaves the winner's refined pose in the scene. A candidate scores inliers x inlier ratio x
// (1 - (rmse / max_dist_last)^2): the points it explains, discounted by the share of its visible
// surface the measurements do not confirm and by how loosely they fit (MSAC). Another candidate
// replaces the first (the detection's own) only when it scores more than (1 + own_margin) times as
// much: on a nearly symmetric shape, or from far away, the scores differ by noise and the detection
// keeps its say. When no candidate refines to kOk the first stays, unrefined. With `world_up` set,
// a candidate whose object z axis points up gains up to upright_bonus of its score (objects rest as
// their meshes are modelled, z up): a closed box upside down explains the depth about as well as
// upright, and the detector's PnP often gives it upside down. With `weak_fits_score`, candidates
// whose refinement did not end kOk (too few points, or a false-hypothesis ratio) score by the same
// formula instead of being passed over: between a far or half-hidden object's poses, a handful of
// points is all the evidence there is.
struct OrientationPrior {
  double own_margin = 0.05;
  std::optional<Eigen::Vector3d> world_up;
  double upright_bonus = 0.2;
  bool weak_fits_score = false;
};
OrientationChoice chooseOrientation(RaycastScene& scene, const RefineTarget& target,
                                    const std::vector<Eigen::Isometry3d>& candidates,
                                    const std::vector<RangeMeasurements>& measurements,
                                    const RefinerOptions& refiner,
                                    const OrientationPrior& prior = {});

}  // namespace sgt
