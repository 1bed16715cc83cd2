// Object pose refinement by ray-cast correspondences and Umeyama (the paper's core step).
//
// Each round casts the measured rays that can see the objects from the current estimates into
// the scene (objects as instances plus the static map). A ray whose cast hits an object and whose
// measured range lies within the round's threshold of the hit pairs the measured point with the
// model surface point (occlusion between objects is handled by construction: the ray hits the
// front object). Rays that hit the map or nothing give no ray pair. Per object, inner
// steps reuse the round's pairs and move the model side with the running estimate (see
// StepSolver). The threshold shrinks geometrically from the first to the last round. Measured
// points near an object that no ray pair explains pull the model towards them (closest point on
// its surface), which ray-cast pairs alone cannot do once the error exceeds the object's
// thickness or the rays alias (see RefinerOptions::pull_radius). A round's update moves no
// corner of the object's box farther than its pairs reach.
#pragma once

#include <vector>

#include "scene_graph_tracker/registration/ray_correspondences.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/sensors/range_noise.hpp"

namespace sgt {

struct RefinerOptions {
  // Ray-casting rounds x inner steps per frame. The paper used 4 x 10 with Umeyama steps; with
  // the linear point-to-plane step, 3 inner steps converge each round and sideways errors need
  // more fresh casts (ray-cast pairs see a shift mostly through the silhouette), so 8 x 3.
  int rounds = 8;
  int steps = 3;
  StepSolver solver = StepSolver::kLinearPointToPlane;
  float max_dist_first = 0.06f;  // correspondence threshold in the first round (m)
  float max_dist_last = 0.012f;  // ... in the last round
  // Object boxes grow by this much when picking the rays to cast, or by the object's pull radius
  // where smaller: a ray farther out neither hits the object nor measures a point that may pull it.
  float roi_margin = 0.04f;
  // Depth images: every ray_stride-th pixel in x and y in all rounds but the last, which casts
  // every ray of the region when full_resolution_last_round is set (it gives the assignment of
  // every measurement near the objects; a pipeline that pre-segments the frame anyway can turn it
  // off). LiDAR scans are always cast in full: few of their rays fall on objects.
  int ray_stride = 2;
  bool full_resolution_last_round = true;
  // The sampled rounds cast at most about this many depth-image rays near each object (0: no
  // bound): a near object's region is sampled at the coarser stride that brings it down to about
  // that many, so its cost does not grow with its pixel count. Its quality counts (inliers,
  // expected, information) weigh each cast ray by the rays it stands for, so they do not depend on
  // the sampling.
  int max_rays_per_object = 0;
  // Each sampled round shifts its ray grid by an offset below the stride (TileSet::sampled's
  // phase), so successive rounds cast different rays and the grid's aliasing of the object's
  // silhouette does not repeat from round to round.
  bool jitter = false;
  // An object whose round moved no corner of its box by more than this (m) has converged: its
  // rays are not cast in later rounds, and its quality comes from that round's pairs counted at
  // the last round's tolerance (what a cast at it would pair). 0: every object takes all rounds.
  double converged_step = 0.0;
  // Weigh the pairs of each sensor by what one of its cast rays tells: the rays it stands for
  // (max_rays_per_object) over the variance of the sensor's range noise (`noise`) at the object's
  // range, relative to the first measurement set's. A LiDAR's centimetre returns then do not
  // outvote a depth camera's millimetre ones; the pairs of a fit from one set all weigh 1.
  bool weigh_by_noise = true;
  // How much a target's prior (RefineTarget::prior_information) counts against its pairs, which
  // count by the noise of the first measurement set at the object's range: 1 makes each fit the
  // maximum a posteriori pose, 0 ignores the priors. A far or small object whose few noisy rays
  // say less than its prediction then stays near the prediction instead of following the noise.
  double prior_weight = 0.0;
  // Pull pairs (unexplained_pairs.hpp) widen the basin: in every round, measurements the cast
  // leaves unexplained (more than pull_front_margin in front of the predicted surface, within
  // roi_margin of an object's box) pair with the closest point of the object's surface within
  // pull_radius (0 turns them off). In the first pull_point_to_point_rounds rounds they count as
  // point-to-point terms: with tangent planes a thin or round object (the screwdriver) slides and
  // tilts along its own surface from a 10 deg error; later as point-to-plane, which converges
  // faster near the optimum. From 3 cm / 10 deg on the paper frame, mean ADD-S 15.6 -> 0.3 mm.
  float pull_radius = 0.04f;
  float pull_front_margin = 0.01f;
  int pull_point_to_point_rounds = 2;
  // Which rays count as the object's (inliers, expected, assignment, no pulls): those within the
  // round's threshold, widened per ray to noise_sigmas of the sensor's range noise where that is
  // larger, so that a far object's correct returns stay its inliers (0: no widening). The fit
  // itself moves the object by the pairs within the round's own threshold only.
  float noise_sigmas = 0.0f;
  RangeNoise noise;
  double min_inlier_ratio = 0.3;  // below it an object counts as a false hypothesis
  double step_tolerance = 1e-6;   // inner steps stop when an update moves less (m, rad)
  // Fill ObjectQuality::information (a 6 x 6 sum per pair; a caller that does not weight its fits
  // by it saves that work).
  bool information = true;
  AlignmentOptions alignment;
};

enum class RefineStatus {
  kOk,
  kNotVisible,       // no ray of any sensor hits the object: pose kept
  kTooFewPoints,     // visible, but fewer inliers than alignment.min_points: pose kept
  kDegenerate,       // inliers are collinear or planar: pose kept from then on
  kFalseHypothesis,  // inlier ratio below min_inlier_ratio: likely nothing there
  kImplausibleTurn,  // set by the tracker: turned farther than the track's motion model allows
};
const char* toString(RefineStatus s);

struct ObjectQuality {
  int inliers = 0;   // measured points paired with the object in the last round
  int expected = 0;  // valid measurements whose ray hits the object at the final estimate
  double inlier_ratio = 0.0;
  // The share of `expected` within the last round's own threshold (inlier_ratio counts the rays
  // within the noise band, RefinerOptions::noise_sigmas): how closely the pose explains them.
  double close_ratio = 0.0;
  double rmse = 0.0;  // of the inliers' point-to-point residuals (m)
  // Root mean square of each inlier's residual over its threshold: 0 on the surface, 1 when every
  // inlier lies at its threshold.
  double rms_of_threshold = 0.0;
  AlignmentStatus last_alignment = AlignmentStatus::kOk;
  RefineStatus status = RefineStatus::kNotVisible;
  // What the last round's pairs constrain: the sum of J J^T of their point-to-plane residuals for
  // a pose change [translation, rotation about the object's origin] in the world frame, per unit
  // noise. Its small eigenvalues are the directions the fit leaves free (a box seen only from
  // above slides and turns in its top plane unseen).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

struct RefineTarget {
  NodeId node;
  const Symmetry* symmetry = nullptr;  // continuous symmetries are not fought: no spin about them
  // This object's pull radius when below RefinerOptions::pull_radius (negative: that one). The
  // pipeline gives each track the distance its filter lets it have moved, so that unexplained
  // points farther away (unknown things beside it) do not pull a well-tracked object.
  float pull_radius = -1.0f;
  // Where the object is expected and how surely: the inverse covariance of that pose
  // ([translation, rotation] in the world frame, rotation perturbing on the left; per m and rad).
  // Zero: no prior (RefinerOptions::prior_weight).
  Eigen::Isometry3d T_prior = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> prior_information = Eigen::Matrix<double, 6, 6>::Zero();
};

struct ObjectEstimate {
  NodeId node;
  Eigen::Isometry3d T_world_object;
  ObjectQuality quality;
};

struct RefineResult {
  std::vector<ObjectEstimate> objects;          // in the order of the targets
  std::vector<std::vector<NodeId>> assignment;  // per measurement set, per ray: object or kNoNode
  std::size_t rays_cast = 0;
};

// `max_dist` widened to o.noise_sigmas of the sensor's noise: for depth images, whose noise grows
// with range squared (and can be measured); a LiDAR's small constant noise keeps `max_dist`.
RangeTolerance noiseBand(const RangeMeasurements& m, float max_dist, const RefinerOptions& o);

class ObjectRefiner {
 public:
  explicit ObjectRefiner(const RefinerOptions& options = {}) : options_(options) {}
  const RefinerOptions& options() const { return options_; }
  void setOptions(const RefinerOptions& o) { options_ = o; }

  // Refines the instances of `targets` in `scene` (their current poses are the initial
  // estimates) against the measurements; leaves the refined poses in the scene, committed.
  RefineResult refine(RaycastScene& scene, const std::vector<RefineTarget>& targets,
                      const std::vector<RangeMeasurements>& measurements) const;

 private:
  RefinerOptions options_;
};

}  // namespace sgt
