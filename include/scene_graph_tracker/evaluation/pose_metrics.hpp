// Pose error metrics with BOP's conventions (reference.md): ADD, ADD-S, symmetry-aware
// translation and rotation errors, and recall at 10 % of the object's diameter.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"

namespace sgt {

// Mean distance between the model points under the estimated and the true pose.
double addError(const std::vector<Eigen::Vector3f>& model_points, const Eigen::Isometry3d& T_est,
                const Eigen::Isometry3d& T_true);
// Mean distance from each model point under the estimate to the closest model point under the
// truth (brute force: keep model_points to a few hundred).
double addSError(const std::vector<Eigen::Vector3f>& model_points, const Eigen::Isometry3d& T_est,
                 const Eigen::Isometry3d& T_true);

// An object's surface for exact ADD-S: distances from points (object frame) to the closest point
// of its mesh, by Embree point queries on the mesh's BVH.
class ModelSurface {
 public:
  explicit ModelSurface(std::shared_ptr<const TriangleMesh> mesh);
  // Distance of p to the surface; `radius` when nothing is that close.
  float distance(const Eigen::Vector3f& p, float radius) const;

 private:
  RaycastScene scene_;
  MeshId mesh_;
};

// ADD-S against the surface itself: mean distance from each model point under the estimate to
// the closest point of the surface under the truth (no sampling error, whatever the pose).
double addSError(const std::vector<Eigen::Vector3f>& model_points, const ModelSurface& surface,
                 const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_true);

// Smallest angle (degrees) between R_est and R_true S over the symmetries S; with a continuous
// symmetry, the tilt of its axis only (its twist is unobservable). PoseErrors::rotation_deg.
double symmetricRotationErrorDeg(const Symmetry& symmetry, const Eigen::Matrix3d& R_est,
                                 const Eigen::Matrix3d& R_true);

struct PoseErrors {
  double add =
      0.0;  // ADD, minimised over the symmetries (BOP's ADD for symmetric objects is ADD-S)
  double add_s = 0.0;         // ADD-S: to the surface when given, else sampled; never above `add`
  double translation = 0.0;   // |t_est - t_true| (m)
  double rotation_deg = 0.0;  // smallest angle between R_est and R_true S over the symmetries S
  bool correct = false;       // ADD-S < 10 % of the diameter (BOP recall criterion)
  // The honest error: ADD for a class without declared symmetries (a box turned by 180 deg is
  // wrong), ADD-S for one with them (BOP, PoseCNN); and whether it is below 10 % of the diameter.
  double add_or_adds = 0.0;
  bool correct_add_or_adds = false;
  // Where the estimate is, alone, 10 % of the diameter or more from the object: a wrong
  // ADD(-S) is then a wrong place, else a wrong turn.
  bool displaced = false;
  // Set by the caller that pairs estimates with objects: the estimate lies within 10 % of the
  // diameter of another object of its class (identical objects side by side, their estimates
  // paired crosswise), so a displaced estimate is another object's, not a wrong place.
  bool crossed = false;
};

// Everything for one estimate of an object of class `object` (its mesh sampled with
// `model_points`, e.g. 500 area-uniform surface points). With `surface` (of the same mesh),
// ADD-S is measured to the surface; without, to the closest sample, which overestimates it by up
// to half the samples' spacing once the estimate is off by more than that (a box turned into
// its near-twin: 7 mm on the material box with 500 samples, under 1 mm to the surface).
PoseErrors poseErrors(const ObjectClass& object, const std::vector<Eigen::Vector3f>& model_points,
                      const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_true,
                      const ModelSurface* surface = nullptr);

// poseErrors for every class of a catalog, with `points` surface samples and the exact surface
// of each class's mesh (what evaluate and evaluate_detector score with).
class PoseScorer {
 public:
  explicit PoseScorer(const ObjectCatalog& catalog, std::size_t points = 500);
  PoseErrors operator()(const std::string& class_name, const Eigen::Isometry3d& T_est,
                        const Eigen::Isometry3d& T_true) const;

 private:
  const ObjectCatalog& catalog_;
  std::map<std::string, std::vector<Eigen::Vector3f>> points_;
  std::map<std::string, std::unique_ptr<ModelSurface>> surfaces_;
};

}  // namespace sgt
