// Robot self-localization against the static map mesh (MICP-L style), with the same ray-cast
// correspondences and alignment steps as object refinement.
//
// Each round casts the measurements' rays from the sensors at the current robot pose, pairs every
// measurement whose ray hits the static map within the round's threshold with that hit, and
// solves for the base-frame correction with point-to-plane steps against the map's normals
// (NormalSide::kFixed). Rays that hit a tracked object are explained by it but do not pull the
// robot. The threshold adapts: it starts wide enough for the expected initial error and then
// follows the residuals (3 x their robust sigma, 1.4826 x the median absolute residual, so that
// people and moved furniture do not hold it open), never below max_dist_min.
#pragma once

#include <vector>

#include "scene_graph_tracker/registration/ray_correspondences.hpp"

namespace sgt {

struct LocalizerOptions {
  int rounds = 12;
  int steps = 3;
  StepSolver solver = StepSolver::kLinearPointToPlane;
  float max_dist_start = 0.6f;  // first round's threshold (m): covers 30 cm / 5 deg starts
  float max_dist_min = 0.05f;  // the adaptive threshold never goes below (sensor noise + map error)
  float residual_factor = 3.0f;  // next threshold = factor x robust sigma of the inliers' residuals
  // Every image_stride-th pixel of depth images and every scan_stride-th column and ring of LiDAR
  // grids is cast: the map constrains the robot from far fewer rays than the sensors measure.
  // Sets of one ray per return (PointRays: laser scans, unorganized clouds) are cast whole.
  int image_stride = 4;
  int scan_stride = 2;
  int min_inliers = 200;
  double min_inlier_ratio = 0.3;        // inliers / valid measurements whose ray hits the map
  double converged_translation = 5e-4;  // a round that moves less (m and rad) ends the search
  double converged_rotation = 1e-4;
  double step_tolerance = 1e-7;
  // Ground robot: correct x, y and yaw only (z, roll and pitch stay with the prior). A VLP-16's
  // +-15 deg barely sees floor and ceiling, so a 6-DoF solve lets small roll/pitch errors grow
  // over frames and then holds the threshold open.
  bool planar = true;
  AlignmentOptions alignment;
};

enum class LocalizeStatus {
  kOk,
  kTooFewInliers,  // the measurements do not fit the map around the guess: prior kept
  kDegenerate,  // the map points seen constrain too few directions (e.g. only a floor): prior kept
  kNotConverged,  // still moving after all rounds: prior kept
};
const char* toString(LocalizeStatus s);

struct LocalizeResult {
  Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();  // the prior when status != kOk
  Eigen::Isometry3d T_map_base_estimate = Eigen::Isometry3d::Identity();  // where the search ended
  LocalizeStatus status = LocalizeStatus::kTooFewInliers;
  int inliers = 0;
  int expected = 0;  // valid measurements whose ray hits the map at the final estimate
  double inlier_ratio = 0.0;
  double rmse = 0.0;  // point-to-point residual of the inliers (m)
  float final_threshold = 0.0f;
  int rounds = 0;
  std::size_t rays_cast = 0;
};

class Localizer {
 public:
  explicit Localizer(const LocalizerOptions& options = {}) : options_(options) {}
  const LocalizerOptions& options() const { return options_; }
  void setOptions(const LocalizerOptions& o) { options_ = o; }

  // `measurements` carry their sensor poses for the robot at `T_map_base_prior` (T_world_sensor =
  // T_map_base_prior * T_base_sensor); the map is the scene's static map node.
  LocalizeResult localize(const RaycastScene& scene,
                          const std::vector<RangeMeasurements>& measurements,
                          const Eigen::Isometry3d& T_map_base_prior) const;

 private:
  LocalizerOptions options_;
};

}  // namespace sgt
