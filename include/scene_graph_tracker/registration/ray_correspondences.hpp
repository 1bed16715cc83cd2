// Ray-cast correspondences (RMCL style), shared by object refinement and localization: each
// valid measurement is paired with the surface point its own ray hits in the scene, when the hit
// belongs to a group of interest and lies within a distance threshold. Plus the iterated
// Umeyama solve over a fixed set of pairs.
#pragma once

#include <vector>

#include "scene_graph_tracker/registration/umeyama.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

struct RayPair {
  Eigen::Vector3f measured;  // world frame, from the sensor pose the rays were cast from
  Eigen::Vector3f model;     // world hit point
  Eigen::Vector3f normal;    // world, unit
  std::uint32_t ray;         // index into the measurement set
};

// Maps scene-graph node ids to groups (e.g. object index, or 0 for "the static map").
class NodeGroups {
 public:
  void set(NodeId node, int group);
  int operator()(NodeId node) const {
    return node >= 0 && static_cast<std::size_t>(node) < group_.size() ? group_[node] : -1;
  }
  int groupCount() const { return groups_; }

 private:
  std::vector<int> group_;
  int groups_ = 0;
};

struct PairingStats {
  // Per group: valid measurements whose ray hits the group no farther than the measurement plus
  // max_dist, i.e. the points the group should show (a surface hidden behind something unknown
  // that is closer is not expected to show).
  std::vector<int> expected;
  // When set (before the call), `expected` counts with this tolerance instead of max_dist (it must
  // not exceed max_dist): what a cast at that tighter tolerance would count.
  const RangeTolerance* expected_within = nullptr;
};

// Casts `tiles` of `m` (each ray only up to its measured range r + max_dist.at(r)) and returns
// the accepted pairs per group (|hit range - r| < max_dist.at(r)). `hits` is scratch space reused
// between calls.
std::vector<std::vector<RayPair>> collectRayPairs(const RaycastScene& scene,
                                                  const RangeMeasurements& m, const TileSet& tiles,
                                                  const NodeGroups& groups,
                                                  const RangeTolerance& max_dist, RayHits& hits,
                                                  PairingStats* stats = nullptr);

enum class NormalSide { kMoving, kFixed };

// How each inner step solves for the update over the fixed pairs:
// - kUmeyamaPointToPoint: Umeyama on the pairs (RMCL "P2P"); with ray-cast pairs both points
//   lie on one ray, so this only corrects along the rays and converges poorly sideways.
// - kUmeyamaPointToPlane: Umeyama between each moving point and the foot of its partner on the
//   tangent plane (RMCL "P2L"); a fixed-point iteration that needs many steps when only a few
//   faces constrain a direction.
// - kLinearPointToPlane: the point-to-plane least-squares step (6x6 normal equations, also
//   mergeable sums), converging in a few steps; the package's default.
enum class StepSolver { kUmeyamaPointToPoint, kUmeyamaPointToPlane, kLinearPointToPlane };

struct IterativeAlignment {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // moves `moving` onto `fixed`
  AlignmentStatus status = AlignmentStatus::kTooFewPoints;
  int steps = 0;
  PairMoments
      last;  // of the pairs at the last step that summed them (the first, for the linear step)
};

// A prior on the moving side's pose, in the frame the points are given in: the pose it is
// expected at (moving -> fixed, as IterativeAlignment::T) and the information of that expectation
// ([rotation, translation], the rotation perturbing on the left, in the units of the pairs'
// weighted squared residuals). The linear point-to-plane step then minimises the pairs' residuals
// plus the prior's: a maximum a posteriori step, which moves a pose the pairs barely constrain
// little from where it was expected.
struct AlignmentPrior {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

// Up to `steps` steps over fixed pairs; the moving side follows the running estimate.
// Point-to-plane uses the tangent plane of whichever side carries the normals. Stops early when
// an update is below `tolerance`, or when the set is degenerate (too few, collinear or planar
// points: the estimate reached so far is kept). `weights` (one per pair, optional) weigh the
// pairs' rows in the linear point-to-plane step; the Umeyama solvers and the degeneracy check
// count every pair alike. `prior` (optional) adds its term to the linear point-to-plane step.
IterativeAlignment alignPairs(const std::vector<Eigen::Vector3f>& moving,
                              const std::vector<Eigen::Vector3f>& fixed,
                              const std::vector<Eigen::Vector3f>& normals, NormalSide normal_side,
                              StepSolver solver, int steps, double tolerance,
                              const AlignmentOptions& options,
                              const std::vector<float>* weights = nullptr,
                              const AlignmentPrior* prior = nullptr);

}  // namespace sgt
