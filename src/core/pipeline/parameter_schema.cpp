// The parameter schema: every tracker and detector parameter, declared once (see
// parameter_schema.hpp). A row: name, group, the field it sets, [min, max] and unit for numbers,
// whether it can change at run time, one line of doc. Type and default come from the field.
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <type_traits>

#include "scene_graph_tracker/geometry/mesh_io.hpp"

namespace sgt::params {
namespace {

constexpr bool kRuntime = true;  // dynamic_reconfigure changes it while the tracker runs
constexpr bool kStart = false;   // read when the nodelet starts

template <class T>
constexpr Type typeOf() {
  if constexpr (std::is_same_v<T, bool>)
    return Type::kBool;
  else if constexpr (std::is_same_v<T, int>)
    return Type::kInt;
  else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>)
    return Type::kDouble;
  else {
    static_assert(std::is_same_v<T, std::string>,
                  "parameters are bool, int, float, double or string");
    return Type::kString;
  }
}

// A parameter bound to the field that `ref` returns (a reference into the options).
template <class O, class Ref>
Param<O> bind(const char* name, const char* group, Ref ref, const char* doc) {
  using T = std::remove_reference_t<std::invoke_result_t<Ref, O&>>;
  Param<O> p;
  p.name = name, p.group = group, p.doc = doc;
  p.type = typeOf<T>();
  p.single = std::is_same_v<T, float>;
  p.get = [ref](const O& o) -> Value {
    const T& v = ref(const_cast<O&>(o));  // read only
    if constexpr (std::is_same_v<T, float>)
      return static_cast<double>(v);
    else
      return v;
  };
  p.set = [ref](O& o, const Value& v) {
    if constexpr (std::is_same_v<T, float>)
      ref(o) = static_cast<float>(std::get<double>(v));
    else
      ref(o) = std::get<T>(v);
  };
  return p;
}

template <class O, class Ref>
Param<O> number(const char* name, const char* group, Ref ref, double min, double max,
                const char* unit, bool runtime, const char* doc) {
  Param<O> p = bind<O>(name, group, ref, doc);
  p.min = min, p.max = max, p.unit = unit, p.runtime = runtime;
  return p;
}

template <class O, class Ref>
Param<O> flag(const char* name, const char* group, Ref ref, bool runtime, const char* doc) {
  Param<O> p = bind<O>(name, group, ref, doc);
  p.runtime = runtime;
  return p;
}

// A string read at start; `in_file` false for paths, which the launch files set.
template <class O, class Ref>
Param<O> text(const char* name, const char* group, Ref ref, bool in_file, const char* doc) {
  Param<O> p = bind<O>(name, group, ref, doc);
  p.in_file = in_file;
  return p;
}

// A parameter that is no field of its own type (an enum as a switch).
template <class O, class Get, class Set>
Param<O> computed(const char* name, const char* group, Type type, bool runtime, const char* doc,
                  Get get, Set set) {
  Param<O> p;
  p.name = name, p.group = group, p.type = type, p.runtime = runtime, p.doc = doc;
  p.get = get, p.set = set;
  return p;
}

#define PIPE(field) \
  [](TrackerParameters & t) -> auto& { return t.pipeline.field; }
#define NODE(field) \
  [](TrackerParameters & t) -> auto& { return t.node.field; }
#define DET(field) \
  [](DetectorParameters & d) -> auto& { return d.field; }

constexpr const char* kNode = "node";
constexpr const char* kAssociation = "association";
constexpr const char* kConfirmation = "confirmation";
constexpr const char* kRemoval = "removal";
constexpr const char* kFilter = "filter";
constexpr const char* kRefinement = "refinement";
constexpr const char* kLocalization = "localization";
constexpr const char* kPresegmentation = "pre-segmentation";
constexpr const char* kRelations = "relations";
constexpr const char* kDetection = "detection";

using T = TrackerParameters;
using D = DetectorParameters;

Schema<T> nodeParams() {
  return {
      text<T>("map_frame", kNode, NODE(map_frame), true,
              "the map frame: tracks, static map, published poses"),
      text<T>("odom_frame", kNode, NODE(odom_frame), true,
              "the odometry frame; the tracker corrects map to odom"),
      text<T>("base_frame", kNode, NODE(base_frame), true, "the robot base frame"),
      text<T>("localization", kNode, NODE(localization), true,
              "own: localize against the static map (map to odom published while converged); "
              "external: map to odom from TF, e.g. amcl (nothing published)"),
      flag<T>("publish_map_odom", kNode, NODE(publish_map_odom), kStart,
              "broadcast the map to odom correction of the own localization while it is "
              "converged"),
      flag<T>("publish_object_tf", kNode, NODE(publish_object_tf), kStart,
              "broadcast the frame of each track below its scene-graph parent (map or the track "
              "it is in or on)"),
      number<T>("hypothesis_max_age", kNode, NODE(hypothesis_max_age), 0.0, 10.0, "s", kStart,
                "the hypothesis array closest to a depth image within this is used with it"),
      number<T>("hypothesis_max_wait", kNode, NODE(hypothesis_max_wait), 0.0, 5.0, "s", kStart,
                "how long a depth image waits for the hypothesis array of its image while that "
                "may still come (wall time; then it goes on with what came); 0: never waits"),
      number<T>("max_time_jitter", kNode, NODE(max_time_jitter), 0.0, 3600.0, "s", kStart,
                "an image older than the last by up to this is dropped; by more, the tracks reset"),
      text<T>("depth_transport", kNode, NODE(depth_transport), true,
              "how depth images arrive: raw, compressed or compressedDepth (image_transport; "
              "tracker.launch depth_transport)"),
      text<T>("static_map", kNode, NODE(static_map), false,
              "the static world as a mesh or URDF file, required (tracker.launch static_map)"),
      text<T>("furniture", kNode, NODE(furniture), false,
              "named boxes for relations, e.g. tables (relations/furniture.hpp; tracker.launch "
              "furniture)"),
      text<T>("catalog", kNode, NODE(catalog), false,
              "object catalog YAML (tracker.launch catalog)"),
      text<T>("mesh_dir", kNode, NODE(mesh_dir), false,
              "another mesh directory for the catalog classes (tracker.launch mesh_dir)"),
      text<T>("track_id_file", kNode, NODE(track_id_file), false,
              "YAML file of the last track number per class: ids are never reused across "
              "restarts (tracker.launch track_id_file; empty: ids start at 1)"),
      number<T>("lidar/columns", kNode, NODE(lidar.columns), 1, 100000, "", kStart,
                "LiDAR: columns (firings) over one turn of an organized cloud"),
      number<T>("lidar/rings", kNode, NODE(lidar.rings), 1, 1024, "", kStart,
                "LiDAR: rings (rows) of the cloud"),
      number<T>("lidar/min_elevation", kNode, NODE(lidar.phi_min), -1.5708, 1.5708, "rad", kStart,
                "LiDAR: elevation of the lowest ring"),
      number<T>("lidar/max_elevation", kNode, NODE(lidar.phi_max), -1.5708, 1.5708, "rad", kStart,
                "LiDAR: elevation of the highest ring"),
      number<T>("lidar/range_min", kNode, NODE(lidar.range_min), 0.0, 1000.0, "m", kStart,
                "LiDAR: shorter returns are no measurement"),
      number<T>("lidar/range_max", kNode, NODE(lidar.range_max), 0.0, 1000.0, "m", kStart,
                "LiDAR: longer returns are no measurement"),
  };
}

Schema<T> associationParams() {
  return {
      number<T>("min_hypothesis_score", kAssociation, PIPE(min_hypothesis_score), 0.0, 1.0, "",
                kRuntime, "hypotheses with a lower score are ignored"),
      number<T>("max_hypotheses_per_frame", kAssociation, PIPE(max_hypotheses_per_frame), 0, 100000,
                "", kRuntime, "the best-scored this many hypotheses of a frame are used"),
      number<T>("max_tracks", kAssociation, PIPE(max_tracks), 0, 100000, "", kRuntime,
                "no track is started beyond this many"),
      number<T>("max_tracks_per_class", kAssociation, PIPE(max_tracks_per_class), 0, 100000, "",
                kRuntime, "nor beyond this many of one class"),
      number<T>("association_distance", kAssociation, PIPE(association_distance), 0.01, 2.0, "m",
                kRuntime, "hypothesis to the predicted position of a track of its class"),
      number<T>("reacquire_distance", kAssociation, PIPE(reacquire_distance), 0.01, 5.0, "m",
                kRuntime,
                "the same for tracks that may have moved: tentative, seen missing, or not refined "
                "where rays reach them (one no ray reaches keeps association_distance)"),
      flag<T>("contest_restarts", kAssociation, PIPE(contest_restarts), kRuntime,
              "a detection restarts a lost track only if the measurements support it better than "
              "the track pose"),
      flag<T>(
          "restart_replaces_outliers", kAssociation, PIPE(restart_replaces_outliers), kRuntime,
          "a restarting detection outside the 99.9 % gate of the track filter replaces its pose "
          "instead of being averaged with it"),
      flag<T>("fuse_hypotheses", kAssociation, PIPE(fuse_hypotheses), kRuntime,
              "a hypothesis associated with a track that it does not restart updates the track "
              "filter as a measurement of its pose where it lies within the 99.9 % gate"),
      number<T>("lost_track_max_jump_m", kAssociation, PIPE(lost_track_max_jump_m), 0.0, 1.0, "m",
                kRuntime,
                "a lost track ignores fits farther than this from where it was lost, until a "
                "hypothesis restarts it"),
      number<T>("lost_track_resume_inlier_ratio", kAssociation,
                PIPE(lost_track_resume_inlier_ratio), 0.0, 1.0, "", kRuntime,
                "... and fits explaining less than this share of the rays that reach it"),
  };
}

Schema<T> confirmationParams() {
  return {
      number<T>("confirm_hits", kConfirmation, PIPE(confirm_hits), 1, 100, "", kRuntime,
                "good refinements that confirm a tentative track ..."),
      number<T>("confirm_detections", kConfirmation, PIPE(confirm_detections), 1, 100, "", kRuntime,
                "... and detections associated with it (the one that started it counts)"),
      number<T>("confirm_inlier_ratio", kConfirmation, PIPE(confirm_inlier_ratio), 0.0, 1.0, "",
                kRuntime, "... and whose fits explain at least this share of their rays"),
      number<T>("confirm_presence_score", kConfirmation, PIPE(confirm_presence_score), 0.0, 100.0,
                "", kRuntime,
                "... and whose model explains the rays near it better than the scene without it "
                "by this score (a second model of a tracked object adds nothing; 0 off)"),
      number<T>("min_weak_fit_inliers", kConfirmation, PIPE(min_weak_fit_inliers), 0, 1000, "",
                kRuntime,
                "a tentative track fit from fewer points than refine/min_points still places the "
                "track from this many"),
      number<T>(
          "fit_support_weight", kConfirmation, PIPE(fit_support_weight), 0.0, 1.0, "", kRuntime,
          "weight per frame of the running mean of the inlier ratios of good fits (fit support)"),
      number<T>("min_fit_support", kConfirmation, PIPE(min_fit_support), 0.0, 1.0, "", kRuntime,
                "fit support that confirms a track; below it a confirmed track collects evidence "
                "of absence"),
  };
}

Schema<T> removalParams() {
  return {
      number<T>("remove_after", kRemoval, PIPE(remove_after_s), 0.1, 30.0, "s", kRuntime,
                "evidence of absence (rays reach where it should be and find something behind) for "
                "this long removes a track"),
      number<T>("remove_tentative_after_s", kRemoval, PIPE(remove_tentative_after_s), 0.0, 30.0,
                "s", kRuntime, "the same for a tentative track"),
      number<T>("tentative_timeout_s", kRemoval, PIPE(tentative_timeout_s), 0.0, 30.0, "s",
                kRuntime,
                "a tentative track in view this long since its last hypothesis goes (time out of "
                "view, where no ray reaches it, does not count)"),
      number<T>("tentative_unseen_timeout_s", kRemoval, PIPE(tentative_unseen_timeout_s), 0.0,
                600.0, "s", kRuntime,
                "a tentative track without a hypothesis for this long goes, in view or not"),
      number<T>("unlocated_keep_s", kRemoval, PIPE(unlocated_keep_s), 0.0, 3600.0, "s", kRuntime,
                "the id of a confirmed track that goes waits this long for the next detection of "
                "its class that no track takes (0: off)"),
      number<T>(
          "max_sunk_fraction", kRemoval, PIPE(max_sunk_fraction), 0.0, 1.0, "", kRuntime,
          "share of the vertices of a model (up to about 64) deeper than sink_tolerance_m inside "
          "the static map that removes the track (1: off; needs an outward-wound map)"),
      number<T>("sink_tolerance_m", kRemoval, PIPE(sink_tolerance_m), 0.0, 0.5, "m", kRuntime,
                "depth behind the map surface that counts as sunk"),
      number<T>(
          "unseen_drop_m", kRemoval, PIPE(unseen_drop_m), 0.0, 1.0, "m", kRuntime,
          "a coasting track seen missing where it is, or out of view, whose fit did not find "
          "it elsewhere, drops straight down by up to this onto what lies below it, and stays "
          "there if it cannot be seen missing there (0: off)"),
      number<T>("absence_noise_sigmas", kRemoval, PIPE(absence_noise_sigmas), 0.0, 10.0, "",
                kRuntime,
                "a ray measured up to this many depth noise sigmas before the surface of a track "
                "counts against its absence, as one beyond it counts for it (0: only rays within "
                "the last refinement threshold)"),
  };
}

Schema<T> filterParams() {
  return {
      number<T>("motion/accel", kFilter, PIPE(motion.accel), 0.0, 100.0, "m/s^2", kRuntime,
                "white-noise acceleration of the constant-velocity model (new tracks)"),
      number<T>("motion/angular_accel", kFilter, PIPE(motion.angular_accel), 0.0, 100.0, "rad/s^2",
                kRuntime, "white-noise angular acceleration (new tracks)"),
      number<T>("motion/initial_velocity", kFilter, PIPE(motion.initial_velocity), 0.0, 100.0,
                "m/s", kRuntime, "1 sigma of the unknown velocity of a new track"),
      number<T>("motion/initial_angular_velocity", kFilter, PIPE(motion.initial_angular_velocity),
                0.0, 100.0, "rad/s", kRuntime,
                "1 sigma of the unknown angular velocity of a new track"),
      number<T>(
          "motion/coast_decay_s", kFilter, PIPE(motion.coast_decay_s), 0.0, 10.0, "s", kRuntime,
          "time constant with which the velocities of a coasting track decay (0: they do not)"),
      number<T>("motion/max_noise_scale", kFilter, PIPE(motion.max_noise_scale), 1.0, 1e4, "",
                kRuntime,
                "largest factor by which the process noise of a track grows while its measurements "
                "show a manoeuvre the constant-velocity model cannot explain (new tracks; 1: off)"),
      number<T>("refined_sigma_m", kFilter, PIPE(refined_sigma_m), 1e-5, 1.0, "m", kRuntime,
                "noise of a refined pose, translation"),
      number<T>("refined_sigma_rad", kFilter, PIPE(refined_sigma_rad), 1e-5, 1.0, "rad", kRuntime,
                "noise of a refined pose, rotation"),
      number<T>("hypothesis_sigma_m", kFilter, PIPE(hypothesis_sigma_m), 1e-5, 1.0, "m", kRuntime,
                "noise of a detection, translation"),
      number<T>("hypothesis_sigma_rad", kFilter, PIPE(hypothesis_sigma_rad), 1e-5, 3.2, "rad",
                kRuntime, "noise of a detection, rotation"),
      number<T>("well_seen_points", kFilter, PIPE(well_seen_points), 1, 100000, "", kRuntime,
                "refinements with fewer inliers count as weaker measurements"),
      number<T>("far_fit_from_m", kFilter, PIPE(far_fit_from_m), 0.0, 100.0, "m", kRuntime,
                "fits of objects farther from the sensor count as weaker, covariance x (range / "
                "this)^4 (0: off)"),
      number<T>("fit_point_sigma_m", kFilter, PIPE(fit_point_sigma_m), 0.0, 1.0, "m", kRuntime,
                "noise of one depth point along its normal: a fit is weaker in the directions its "
                "rays leave unconstrained (0: off)"),
      number<T>("fit_turn_gate", kFilter, PIPE(fit_turn_gate), 0.0, 1e6, "", kRuntime,
                "a fit of a confirmed or lost track turned beyond this chi-square bound (3 dof) of "
                "its predicted rotation is not taken: the track coasts (0: off; 16.27: 99.9 %)"),
  };
}

Schema<T> refinementParams() {
  return {
      number<T>("refine/rounds", kRefinement, PIPE(refiner.rounds), 1, 30, "", kRuntime,
                "ray-casting rounds per frame"),
      number<T>("refine/steps", kRefinement, PIPE(refiner.steps), 1, 20, "", kRuntime,
                "alignment steps per round"),
      number<T>("refine/max_dist_first", kRefinement, PIPE(refiner.max_dist_first), 0.005, 0.5, "m",
                kRuntime, "correspondence threshold of the first round ..."),
      number<T>("refine/max_dist_last", kRefinement, PIPE(refiner.max_dist_last), 0.002, 0.2, "m",
                kRuntime, "... shrinking to this in the last"),
      number<T>("refine/roi_margin", kRefinement, PIPE(refiner.roi_margin), 0.0, 0.5, "m", kRuntime,
                "object boxes grow by this much (or their pull radius where smaller) when "
                "picking the rays to cast"),
      number<T>("refine/ray_stride", kRefinement, PIPE(refiner.ray_stride), 1, 16, "", kRuntime,
                "every ray_stride-th depth pixel in x and y"),
      number<T>("refine/max_rays_per_object", kRefinement, PIPE(refiner.max_rays_per_object), 0,
                1000000, "", kRuntime,
                "depth rays reaching one object per round at most (the rays of its region until a "
                "round has counted them): a near object is sampled more sparsely (0: every "
                "ray_stride-th)"),
      flag<T>("refine/jitter", kRefinement, PIPE(refiner.jitter), kRuntime,
              "each round shifts the sampled ray grid, so successive rounds cast different rays"),
      flag<T>("refine/weigh_by_noise", kRefinement, PIPE(refiner.weigh_by_noise), kRuntime,
              "the pairs of each sensor count in the fit by the rays they stand for over the "
              "variance of its noise at the range of the object (off: all alike)"),
      number<T>("refine/prior_weight", kRefinement, PIPE(refiner.prior_weight), 0.0, 100.0, "",
                kRuntime,
                "how much the predicted pose of a track counts in its fit against the rays, which "
                "count by the noise of the sensor: 1 makes the fit the most probable pose given "
                "both (0: off)"),
      number<T>("refine/converged_step", kRefinement, PIPE(refiner.converged_step), 0.0, 0.1, "m",
                kRuntime,
                "an object whose round moves no box corner farther has converged: its rays are no "
                "longer cast (0: all rounds)"),
  };
}

// Pulls towards unexplained points, and when a fit counts.
Schema<T> pullParams() {
  return {
      number<T>("refine/pull_radius", kRefinement, PIPE(refiner.pull_radius), 0.0, 0.5, "m",
                kRuntime,
                "unexplained measurements this close to an object pull it towards them (0: off)"),
      number<T>(
          "refine/pull_sigmas", kRefinement, PIPE(pull_sigmas), 0.0, 100.0, "", kRuntime,
          "... and, once the track is confirmed, no farther than this many standard deviations "
          "of its predicted position (0: pull_radius)"),
      number<T>("refine/pull_front_margin", kRefinement, PIPE(refiner.pull_front_margin), 0.0, 0.5,
                "m", kRuntime,
                "... when they lie more than this in front of its predicted surface"),
      number<T>("refine/pull_point_to_point_rounds", kRefinement,
                PIPE(refiner.pull_point_to_point_rounds), 0, 30, "", kRuntime,
                "first rounds in which pulls are point-to-point terms (then point-to-plane)"),
      number<T>(
          "refine/min_inlier_ratio", kRefinement, PIPE(refiner.min_inlier_ratio), 0.0, 1.0, "",
          kRuntime,
          "a fit explaining less of the rays reaching the object counts as a false hypothesis"),
      number<T>("refine/noise_sigmas", kRefinement, PIPE(refiner.noise_sigmas), 0.0, 20.0, "",
                kRuntime,
                "a depth ray counts as an object inlier within this many sigmas of the depth "
                "noise where wider than the threshold; fits move by the threshold alone (0: off)"),
      number<T>("refine/min_points", kRefinement, PIPE(refiner.alignment.min_points), 3, 100000, "",
                kRuntime, "fewest inliers of a fit"),
      flag<T>("refine_with_lidar", kRefinement, PIPE(refine_with_lidar), kRuntime,
              "refine from LiDAR returns too when the frame has a depth image"),
  };
}

// Which way a track is turned: orientation searches, disputes, and the refiner they use.
Schema<T> orientationParams() {
  return {
      flag<T>("search_orientations", kRefinement, PIPE(search_orientations), kRuntime,
              "a confirmed or restarting track tries the 24 axis turns of its box (tracker.launch "
              "sets it to "
              "detector, evaluate --detector turns it on)"),
      number<T>("max_orientation_searches", kRefinement, PIPE(max_orientation_searches), 0, 100, "",
                kRuntime, "orientation searches per frame (others wait a frame)"),
      number<T>("orientation_search_interval_s", kRefinement, PIPE(orientation_search_interval_s),
                0.0, 3600.0, "s", kRuntime, "a track is searched again no sooner than this"),
      number<T>("research_below_fit_support", kRefinement, PIPE(research_below_fit_support), 0.0,
                1.0, "", kRuntime,
                "a confirmed track whose fit support stays below this is searched again (0: off)"),
      number<T>("twin_tests_per_frame", kRefinement, PIPE(twin_tests_per_frame), 0, 1000, "",
                kRuntime,
                "confirmed tracks per frame (in turn) whose pose is weighed against its near "
                "twins on the depth (0: off)"),
      number<T>("twin_switch_log_odds", kRefinement, PIPE(twin_switch_log_odds), 0.0, 1000.0, "",
                kRuntime, "a track turns to a twin whose accumulated log odds exceed this"),
      number<T>("twin_frame_cap", kRefinement, PIPE(twin_frame_cap), 0.0, 1000.0, "", kRuntime,
                "the score of one frame counts at most this much towards a twin"),
      number<T>("orientation_dispute_deg", kRefinement, PIPE(orientation_dispute_deg), 0.0, 180.0,
                "deg", kRuntime,
                "a hypothesis turned more than this from its track (up to symmetries) disputes "
                "its orientation (0: off)"),
      number<T>("orientation_disputes", kRefinement, PIPE(orientation_disputes), 0, 1000, "",
                kRuntime,
                "disputing hypotheses in a row that make the pose of the detection compete with "
                "that of the track, both refined on the measurements (0: off)"),
      number<T>("position_disputes", kRefinement, PIPE(position_disputes), 0, 1000, "", kRuntime,
                "hypotheses in a row placed beyond the 99.9 % bound of the predicted position "
                "of a track that make its pose, moved to the detection, compete with it, both "
                "refined on the measurements (0: off)"),
      number<T>("orientation_refine/rounds", kRefinement, PIPE(orientation_refiner.rounds), 1, 30,
                "", kRuntime, "ray-casting rounds per candidate of a search or restart contest"),
      number<T>("orientation_refine/steps", kRefinement, PIPE(orientation_refiner.steps), 1, 20, "",
                kRuntime, "alignment steps per round"),
      number<T>("orientation_refine/max_dist_first", kRefinement,
                PIPE(orientation_refiner.max_dist_first), 0.005, 0.5, "m", kRuntime,
                "correspondence threshold of the first round ..."),
      number<T>("orientation_refine/max_dist_last", kRefinement,
                PIPE(orientation_refiner.max_dist_last), 0.002, 0.2, "m", kRuntime,
                "... shrinking to this in the last"),
      number<T>("orientation_refine/ray_stride", kRefinement, PIPE(orientation_refiner.ray_stride),
                1, 16, "", kRuntime, "every ray_stride-th depth pixel in x and y"),
  };
}

Schema<T> localizationParams() {
  return {
      flag<T>("localize", kLocalization, PIPE(localize), kRuntime,
              "correct the robot pose against the static map (needs the LiDAR)"),
      flag<T>(
          "localize_with_lidar_only", kLocalization, PIPE(localize_with_lidar_only), kRuntime,
          "localize from LiDAR scans only (depth images near a bench add little but cost rays)"),
      flag<T>("localize_against_objects", kLocalization, PIPE(localize_against_objects), kRuntime,
              "tracked objects explain points while the robot localizes"),
      number<T>("localizer/rounds", kLocalization, PIPE(localizer.rounds), 1, 100, "", kRuntime,
                "ray-casting rounds per frame"),
      number<T>("localizer/steps", kLocalization, PIPE(localizer.steps), 1, 20, "", kRuntime,
                "alignment steps per round"),
      number<T>("localizer/max_dist_start", kLocalization, PIPE(localizer.max_dist_start), 0.01,
                5.0, "m", kRuntime, "correspondence threshold of the first round"),
      number<T>("localizer/max_dist_min", kLocalization, PIPE(localizer.max_dist_min), 0.001, 1.0,
                "m", kRuntime, "the adaptive threshold never goes below this"),
      number<T>("localizer/residual_factor", kLocalization, PIPE(localizer.residual_factor), 0.5,
                20.0, "", kRuntime, "next threshold: this times the robust sigma of the residuals"),
      number<T>("localizer/image_stride", kLocalization, PIPE(localizer.image_stride), 1, 64, "",
                kRuntime, "every image_stride-th depth pixel in x and y"),
      number<T>("localizer/scan_stride", kLocalization, PIPE(localizer.scan_stride), 1, 64, "",
                kRuntime, "every scan_stride-th LiDAR column and ring"),
      number<T>("localizer/min_inliers", kLocalization, PIPE(localizer.min_inliers), 1, 1000000, "",
                kRuntime, "fewer inliers keep the prior"),
      number<T>("localizer/min_inlier_ratio", kLocalization, PIPE(localizer.min_inlier_ratio), 0.0,
                1.0, "", kRuntime,
                "inliers per valid measurement whose ray hits the map, below it the prior is kept"),
      number<T>("localizer/converged_translation", kLocalization,
                PIPE(localizer.converged_translation), 0.0, 1.0, "m", kRuntime,
                "a round that moves less (and less than converged_rotation) ends the search"),
      number<T>("localizer/converged_rotation", kLocalization, PIPE(localizer.converged_rotation),
                0.0, 1.0, "rad", kRuntime, "see converged_translation"),
      flag<T>("localizer/planar", kLocalization, PIPE(localizer.planar), kRuntime,
              "correct x, y and yaw only (a ground robot)"),
  };
}

Schema<T> presegmentationParams() {
  return {
      flag<T>("presegment", kPresegmentation, PIPE(run_presegmentation), kRuntime,
              "label every measurement; unknown points on ~unassigned_points"),
      number<T>(
          "presegmentation/sigma_factor", kPresegmentation, PIPE(presegmentation.sigma_factor), 0.5,
          20.0, "", kRuntime,
          "a measurement agrees with the predicted surface within this many noise sigmas ..."),
      number<T>("presegmentation/min_tolerance", kPresegmentation,
                PIPE(presegmentation.min_tolerance), 0.0, 1.0, "m", kRuntime,
                "... and never less than this (map and mesh error)"),
      number<T>("presegmentation/depth_sigma_at_1m", kPresegmentation,
                PIPE(presegmentation.noise.depth_sigma_at_1m), 0.0, 0.1, "m", kRuntime,
                "depth image noise at 1 m, growing with range squared"),
      flag<T>("presegmentation/measure_depth_noise", kPresegmentation, PIPE(measure_depth_noise),
              kRuntime,
              "measure depth_sigma_at_1m on the static map in every frame (the setting starts it)"),
      number<T>("presegmentation/range_sigma", kPresegmentation,
                PIPE(presegmentation.noise.range_sigma), 0.0, 1.0, "m", kRuntime,
                "LiDAR range noise"),
      flag<T>("presegmentation/map_planes", kPresegmentation, PIPE(presegmentation.map_planes),
              kRuntime,
              "depth pixels whose 4 x 4 block sees one plane of the map take their predicted "
              "range from that plane, not from a cast of their own"),
  };
}

Schema<T> relationsParams() {
  return {
      flag<T>("relations/enabled", kRelations, PIPE(compute_relations), kStart,
              "relations among confirmed tracks and the workbench, edges on ~scene_graph"),
      flag<T>("relations/reparent", kRelations, PIPE(reparent), kStart,
              "a track in or on another becomes its child (and is predicted with it)"),
      flag<T>("relations/directional", kRelations, PIPE(relation_options.directional), kRuntime,
              "also left_of, right_of, in_front_of, behind, above, below among tracks"),
      computed<T>(
          "relations/relaxed", kRelations, Type::kBool, kRuntime,
          "directions: relaxed (halfspace intersects) instead of strict (projection contains)",
          [](const T& t) -> Value {
            return t.pipeline.relation_options.directional_mode == relations::Mode::Relaxed;
          },
          [](T& t, const Value& v) {
            t.pipeline.relation_options.directional_mode =
                std::get<bool>(v) ? relations::Mode::Relaxed : relations::Mode::Strict;
          }),
      flag<T>(
          "relations/camera_relative", kRelations, PIPE(relation_options.camera_relative), kRuntime,
          "directions from the point of view of the camera instead of the frame of the reference"),
      number<T>("relations/appear_frames", kRelations, PIPE(relation_hysteresis.appear_frames), 1,
                1000, "", kRuntime, "an edge shows after holding this many frames in a row ..."),
      number<T>("relations/disappear_frames", kRelations,
                PIPE(relation_hysteresis.disappear_frames), 1, 1000, "", kRuntime,
                "... and goes after failing this many"),
      number<T>("relations/min_support", kRelations, PIPE(relation_options.min_support), 0.0, 1.0,
                "", kRuntime, "share of the support rays that makes rests on"),
      number<T>("relations/on_max_distance", kRelations, PIPE(relation_options.box.on_max_distance),
                0.0, 1.0, "m", kRuntime, "on: the boxes are less than this apart"),
      number<T>("relations/box_tolerance", kRelations, PIPE(relation_options.box.tolerance), 0.0,
                1.0, "m", kRuntime,
                "box corners may lie this far outside a box that must contain them"),
      number<T>("relations/extrusion_factor", kRelations, PIPE(relation_options.box.factor), 0.1,
                100.0, "", kRuntime,
                "projections and halfspaces reach this many box extents (SEMAP)"),
  };
}

Schema<T> makeTrackerSchema() {
  Schema<T> s;
  for (Schema<T> group : {nodeParams(), associationParams(), confirmationParams(), removalParams(),
                          filterParams(), refinementParams(), pullParams(), orientationParams(),
                          localizationParams(), presegmentationParams(), relationsParams()})
    s.insert(s.end(), group.begin(), group.end());
  return s;
}

Schema<D> makeDetectorSchema() {
  return {
      number<D>("score_threshold", kDetection, DET(decode.score_threshold), 0.0, 1.0, "", kStart,
                "class score of a detection (after sigmoid); per-class thresholds of the model may "
                "raise it"),
      number<D>("nms_iou", kDetection, DET(decode.nms_iou), 0.0, 1.0, "", kStart,
                "class-aware non-maximum suppression"),
      number<D>("max_detections", kDetection, DET(decode.max_detections), 1, 10000, "", kStart,
                "per image"),
      number<D>("min_visibility", kDetection, DET(pnp.min_visibility), 0.0, 1.0, "", kStart,
                "keypoints below this visibility are not used by PnP"),
      number<D>("max_reprojection_px", kDetection, DET(pnp.max_reprojection_px), 0.0, 1000.0, "px",
                kStart, "RMS; PnP solutions above are rejected"),
      number<D>("min_depth", kDetection, DET(pnp.min_depth), 0.0, 100.0, "m", kStart,
                "the object centre must be at least this far in front of the camera"),
      flag<D>("use_depth", kDetection, DET(use_depth), kStart,
              "distance of each pose from the registered depth image (topic depth)"),
      text<D>("image_transport", kDetection, DET(image_transport), true,
              "how RGB images arrive: raw or compressed (image_transport; tracker.launch "
              "image_transport)"),
      text<D>("depth_transport", kDetection, DET(depth_transport), true,
              "how depth images arrive: raw, compressed or compressedDepth (tracker.launch "
              "depth_transport)"),
      number<D>("depth_max_offset", kDetection, DET(depth_max_offset), 0.0, 1.0, "s", kStart,
                "the depth image closest in time to the RGB image, at most this far"),
      number<D>("depth_max_wait", kDetection, DET(depth_max_wait), 0.0, 1.0, "s", kStart,
                "how long an RGB image waits for its depth image when that may still come "
                "(wall time; then its distances come from PnP alone); 0: never waits"),
      number<D>("busy_interval", kDetection, DET(schedule.busy_interval_s), 0.0, 60.0, "s", kStart,
                "detect an image at most this often while a track is tentative or there is none "
                "(detection/detection_schedule.hpp); 0: every image"),
      number<D>("settled_interval", kDetection, DET(schedule.settled_interval_s), 0.0, 60.0, "s",
                kStart,
                "... while every track is confirmed (the refinement carries them); images not "
                "detected get an empty hypothesis array at once; 0: every image"),
      number<D>("lost_backoff", kDetection, DET(schedule.lost_backoff), 0.0, 100.0, "", kStart,
                "a lost or removed track asks for detection every max(busy_interval, this x "
                "seconds gone), up to settled_interval"),
      number<D>("new_view_share", kDetection, DET(schedule.new_view_share), 0.0, 1.0, "", kStart,
                "an image of which at least this share is new since the last detected one (the "
                "camera turned, something moved away or came closer; detection/view_novelty.hpp) "
                "is detected whatever the interval; 0: off"),
      text<D>("dnn_backend", kDetection, DET(inference.backend), true,
              "OpenCV DNN backend: opencv, cuda or default (cuda on a Jetson with a CUDA build "
              "of OpenCV; what the build cannot run falls back to opencv / cpu, with a warning)"),
      text<D>("dnn_target", kDetection, DET(inference.target), true,
              "OpenCV DNN target: cpu, opencl, opencl_fp16, cuda or cuda_fp16"),
      text<D>("model", kDetection, DET(model), false,
              "metadata YAML beside the ONNX model (tracker.launch detector_model)"),
      text<D>("catalog", kDetection, DET(catalog), false,
              "object catalog YAML (tracker.launch catalog)"),
      text<D>("mesh_dir", kDetection, DET(mesh_dir), false,
              "another mesh directory for the catalog classes (tracker.launch mesh_dir)"),
  };
}

#undef PIPE
#undef NODE
#undef DET

std::string describe(const Value& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using X = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<X, bool>)
          return x ? "true" : "false";
        else if constexpr (std::is_same_v<X, int>)
          return std::to_string(x);
        else if constexpr (std::is_same_v<X, double>)
          return formatNumber(x, false);
        else
          return "'" + x + "'";
      },
      v);
}

template <class O>
Value parseScalar(const Param<O>& p, const YAML::Node& n) {
  try {
    switch (p.type) {
      case Type::kBool:
        return n.as<bool>();
      case Type::kInt:
        return n.as<int>();
      case Type::kDouble:
        return n.as<double>();
      case Type::kString:
        return n.as<std::string>();
    }
  } catch (const YAML::Exception&) {
  }
  throw ParameterError(p.name + ": '" + n.Scalar() + "' is not " +
                       (p.type == Type::kInt ? "an " : "a ") + toString(p.type));
}

// Scalars of a YAML map with '/'-separated names.
void flatten(const YAML::Node& n, const std::string& prefix,
             std::vector<std::pair<std::string, YAML::Node>>& out) {
  for (const auto& kv : n) {
    const std::string name = (prefix.empty() ? "" : prefix + "/") + kv.first.as<std::string>();
    if (kv.second.IsMap())
      flatten(kv.second, name, out);
    else
      out.emplace_back(name, kv.second);
  }
}

}  // namespace

const char* toString(Type t) {
  switch (t) {
    case Type::kBool:
      return "bool";
    case Type::kInt:
      return "int";
    case Type::kDouble:
      return "double";
    case Type::kString:
      return "string";
  }
  return "?";
}

const std::vector<Group>& groups() {
  static const std::vector<Group> g = {
      {kNode, "the nodelet itself: frames, TF, inputs"},
      {kAssociation, "which hypotheses start, update or restart which track"},
      {kConfirmation, "when a tentative track becomes confirmed"},
      {kRemoval, "when a track goes"},
      {kFilter, "the pose filter of each track: motion model and measurement noise"},
      {kRefinement, "ray-cast refinement of the object poses, orientation search"},
      {kLocalization, "the robot pose against the static map"},
      {kPresegmentation, "labelling every measurement as map, object or unknown"},
      {kRelations, "scene-graph edges among tracks and furniture (README Relations)"},
      {kDetection, "the keypoint detector and cuboid PnP"},
  };
  return g;
}

const Schema<TrackerParameters>& trackerSchema() {
  static const Schema<TrackerParameters> s = makeTrackerSchema();
  return s;
}

const Schema<DetectorParameters>& detectorSchema() {
  static const Schema<DetectorParameters> s = makeDetectorSchema();
  return s;
}

template <class O>
const Param<O>* find(const Schema<O>& schema, const std::string& name) {
  for (const Param<O>& p : schema)
    if (p.name == name) return &p;
  return nullptr;
}

template <class O>
void set(const Schema<O>& schema, O& options, const std::string& name, const Value& value) {
  const Param<O>* p = find(schema, name);
  if (!p) throw ParameterError(name + ": no such parameter");
  Value v = value;
  if (p->type == Type::kDouble && std::holds_alternative<int>(v))
    v = static_cast<double>(std::get<int>(v));
  if (static_cast<Type>(v.index()) != p->type)  // Value's alternatives are in the order of Type
    throw ParameterError(name + ": " + describe(value) + " is not " +
                         (p->type == Type::kInt ? "an " : "a ") + toString(p->type));
  if (p->type == Type::kInt || p->type == Type::kDouble) {
    const double x = p->type == Type::kInt ? std::get<int>(v) : std::get<double>(v);
    if (!(x >= p->min && x <= p->max))
      throw ParameterError(name + ": " + describe(value) + " is outside " + range(*p));
  }
  p->set(options, v);
}

template <class O>
void applyYaml(const Schema<O>& schema, O& options, const std::string& text,
               const std::string& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ParameterError(origin + ": " + e.what());
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw ParameterError(origin + ": not a map of parameters");
  std::vector<std::pair<std::string, YAML::Node>> scalars;
  flatten(root, "", scalars);
  for (const auto& [name, node] : scalars) {
    try {
      const Param<O>* p = find(schema, name);
      if (!p) throw ParameterError(name + ": no such parameter");
      if (!node.IsScalar()) throw ParameterError(name + ": no single value");
      set(schema, options, name, parseScalar(*p, node));
    } catch (const ParameterError& e) {
      throw ParameterError(origin + ": " + e.what());
    }
  }
}

template <class O>
void applyYamlFile(const Schema<O>& schema, O& options, const std::string& uri) {
  std::string path = uri;
  try {
    path = resolveResourcePath(uri);
  } catch (const MeshError& e) {
    throw ParameterError(e.what());
  }
  std::ifstream in(path);
  if (!in) throw ParameterError(path + ": cannot read the parameter file");
  std::stringstream text;
  text << in.rdbuf();
  applyYaml(schema, options, text.str(), path);
}

std::string reconfigureName(const std::string& name) {
  std::string n = name;
  for (char& c : n)
    if (c == '/') c = '_';
  return n;
}

template <class O>
std::string range(const Param<O>& p) {
  if (p.type == Type::kInt)
    return "[" + std::to_string(int(p.min)) + ", " + std::to_string(int(p.max)) + "]";
  if (p.type == Type::kDouble)
    return "[" + formatNumber(p.min, false) + ", " + formatNumber(p.max, false) + "]";
  return "";
}

template <class O>
std::string format(const Param<O>& p, const Value& v) {
  if (const double* d = std::get_if<double>(&v)) return formatNumber(*d, p.single);
  if (const std::string* s = std::get_if<std::string>(&v)) return *s;
  return describe(v);
}

#define SGT_INSTANTIATE(O)                                                               \
  template const Param<O>* find(const Schema<O>&, const std::string&);                   \
  template void set(const Schema<O>&, O&, const std::string&, const Value&);             \
  template void applyYaml(const Schema<O>&, O&, const std::string&, const std::string&); \
  template void applyYamlFile(const Schema<O>&, O&, const std::string&);                 \
  template std::string format(const Param<O>&, const Value&);                            \
  template std::string range(const Param<O>&);
SGT_INSTANTIATE(TrackerParameters)
SGT_INSTANTIATE(DetectorParameters)
#undef SGT_INSTANTIATE

}  // namespace sgt::params
