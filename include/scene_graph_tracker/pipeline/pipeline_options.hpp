// The tracker's options: one struct, grouped by the stage that reads them. Defaults here are the
// package's defaults, written only here: the parameter schema (parameter_schema.hpp) names the
// fields users set and generates config/tracker.yaml, cfg/Tracker.cfg and the README tables.
#pragma once

#include "scene_graph_tracker/registration/localizer.hpp"
#include "scene_graph_tracker/registration/object_refiner.hpp"
#include "scene_graph_tracker/relations/relation_hysteresis.hpp"
#include "scene_graph_tracker/relations/scene_relations.hpp"
#include "scene_graph_tracker/segmentation/presegmentation.hpp"
#include "scene_graph_tracker/tracking/pose_filter.hpp"

namespace sgt {

struct PipelineOptions {
  RefinerOptions refiner;
  // Pulls (RefinerOptions::pull_radius) of a confirmed track reach no farther than this many
  // standard deviations of its predicted position: a well-tracked object is not dragged into
  // unknown things beside it, while a restarted one (a detection's uncertainty) is pulled as far
  // as pull_radius, and so is a tentative one. 0: every track pulls as far as pull_radius.
  double pull_sigmas = 3.0;
  LocalizerOptions localizer;
  PresegmentOptions presegmentation;
  // The depth images' noise (presegmentation.noise.depth_sigma_at_1m, which starts it and sets its
  // window) is measured on the static map in every frame (segmentation/depth_noise.hpp) and used
  // by refinement (refiner.noise_sigmas) and pre-segmentation. Off by default: it measures the
  // map's and the camera pose's error too (on the real sequence's desk plane 0.06 m at 1 m).
  bool measure_depth_noise = false;
  PoseFilterNoise motion;
  bool localize = true;
  bool localize_with_lidar_only = true;  // depth images near a bench add little but cost rays
  // Whether tracked objects stay in the scene while the robot localizes (their points are then
  // explained and dropped). Off by default: the robot pose must not depend on object tracks,
  // which may be wrong exactly when the robot pose is (a track a few cm off hides the map
  // behind it); without them, points on objects are outliers that the threshold drops.
  bool localize_against_objects = false;
  // Objects are refined from the depth images of a frame; LiDAR returns (sparse, ~1 cm noise, as
  // much as a thin object's radius) only when the frame has no depth image or when this is set.
  bool refine_with_lidar = false;
  double min_hypothesis_score = 0.3;
  // Bounds against a flood of hypotheses: the best-scored this many per frame are used (in their
  // order), and no track is started beyond the totals; what is left out is counted.
  int max_hypotheses_per_frame = 100;
  int max_tracks = 200;
  int max_tracks_per_class = 50;
  double association_distance = 0.15;  // m, hypothesis to a track's prediction (same class)
  double reacquire_distance = 0.6;     // m, for tracks that may have moved (DetectionAssociation)
  int confirm_hits = 3;                // good refinements that confirm a tentative track ...
  // ... and detections associated with it (the one that started it counts): refinement alone
  // confirms a single false detection on an unknown thing of about the right size.
  int confirm_detections = 3;
  double confirm_inlier_ratio =
      0.55;  // ... and whose fits explain at least this fraction of their rays
  // ... and whose model explains the rays near it better than the scene without it, by this score
  // (registration/twin_evidence.hpp, presenceScore; 0: not weighed).
  double confirm_presence_score = 2.0;
  // A tentative track's fit from fewer inliers than the refiner's alignment.min_points still
  // places the track when it has min_weak_fit_inliers and explains confirm_inlier_ratio of the
  // rays reaching the model: the next frame refines from there rather than from the detection
  // (it counts neither as a hit nor towards fit support).
  int min_weak_fit_inliers = 6;
  // Fit support: the running mean (weight fit_support_weight per frame) of the inlier ratios of
  // a track's good fits (and, when the turn gate refuses a fit, of its model where it is kept),
  // i.e. the share of the rays reaching its model that its measurements agree with (the others pass
  // through the model to something behind it). Confirmation needs it at min_fit_support as well, so
  // a few lucky fits among poor ones do not confirm; a confirmed track below it collects evidence
  // of absence and explains no points in pre-segmentation. A model fitted to a patch of something
  // else (a person) explains a part of its rays; a real object nearly all of them.
  double fit_support_weight = 0.25;
  double min_fit_support = 0.65;
  // A track whose model lies partly inside the static map is nowhere a real object can be:
  // when more than max_sunk_fraction of its mesh's vertices (every k-th, up to about 64) are
  // deeper than sink_tolerance_m behind the map's surface (its triangles' winding side), for
  // remove_after_s, it goes, seen or not: the map hides such a track from every ray, so no other
  // evidence of absence reaches it. Vertices crowd where a shape has detail, so they are not
  // shares of its surface; samples spread by area did worse (doc/experiments.md section 56).
  // Needs a map mesh wound outwards (or towards where it was scanned from); 1 turns it off.
  double max_sunk_fraction = 0.2;
  double sink_tolerance_m = 0.01;
  double remove_after_s = 1.0;  // evidence of absence for this long removes a track
  double remove_tentative_after_s = 0.3;
  // A tentative track goes when it has been in view this long since its last hypothesis: out of
  // view (its fit sees no ray reach it) no detector can confirm it. Out of view it goes only
  // tentative_unseen_timeout_s after its last hypothesis.
  double tentative_timeout_s = 1.0;
  double tentative_unseen_timeout_s = 10.0;
  // A confirmed (or lost) track that goes was seen missing where it stood: its object is
  // somewhere else. Its id waits this long for the next detection of its class that no track
  // takes, whose tentative track then carries it (UnlocatedTracks). 0: the id goes with it.
  double unlocated_keep_s = 60.0;
  double refined_sigma_m = 0.002, refined_sigma_rad = 0.01;  // refined pose noise
  int well_seen_points = 150;  // refinements with fewer inliers count as weaker measurements
  // Depth noise grows with range squared: a fit of an object farther than this from the sensor
  // counts as a weaker measurement, its covariance scaled by (range / far_fit_from_m)^4, so the
  // filter does not follow the scatter of far fits (and its velocity does not carry a hidden
  // track away).
  double far_fit_from_m = 1.0;
  // Noise of one depth point along the surface normal. A fit's covariance grows, beyond
  // refined_sigma, in the directions its rays leave unconstrained (fitCovariance), and such a fit
  // reports the filtered pose: a box seen only from above keeps its predicted place and turn in
  // the top plane instead of the fit's drift along it. 0: off.
  double fit_point_sigma_m = 0.0;
  // A fit of an established track (confirmed or lost, not a child) whose rotation lies beyond
  // this chi-square bound (3 dof) of the track's predicted rotation plus the fit's noise is no
  // measurement of the object: a partly hidden object's few rays (a rim, one face) let the
  // refiner spin or tip it by tens of degrees in a frame. The track coasts instead, and the next
  // detection restarts it; unless the fit explains a larger share of its rays than the track's
  // fits have (then the track was wrong). 0: off; 16.27 is the 99.9 % bound.
  double fit_turn_gate = 16.27;
  // A ray that shows an object missing passes through where its surface should be: its
  // measurement lies beyond it. Depth noise puts as many measurements of a present object before
  // its surface as beyond it, so a ray measured before the surface by up to this many noise sigmas
  // counts against absence as one beyond it counts for it. 0: only rays within the fit's last
  // threshold count against absence.
  double absence_noise_sigmas = 3.0;
  // A coasting track the sensors see missing where it is, or cannot see at all (out of view),
  // drops straight down by up to this onto what lies below it, and stays there when they cannot
  // see it missing there: an object let go into a container vanishes below its rim before it
  // reaches the floor, and one put down fast leaves its track hovering where the hand was,
  // often above the camera's view. Up to a hand's carrying height above a bench. 0: off.
  double unseen_drop_m = 0.5;
  // A lost track ignores fits farther than this from where it was lost, or explaining less than
  // this fraction of the rays that reach it, until a hypothesis restarts it (associate():
  // reacquire_distance); such fits are no evidence of absence either.
  double lost_track_max_jump_m = 0.03;
  double lost_track_resume_inlier_ratio = 0.8;
  double hypothesis_sigma_m = 0.02, hypothesis_sigma_rad = 0.08;  // detection noise
  // A detection restarts a lost track only when the measurements support it better than the
  // track's own pose: both are refined briefly (orientation_refiner), fits from too few points
  // scored too, and the detection must win by the search's own_margin with a fit explaining
  // confirm_inlier_ratio of its rays; a tie (nothing seen of either: a hidden object) keeps the
  // track. A track sunk into the static map (max_sunk_fraction) does not compete: nothing real is
  // there. A keypoint detector's pose of a thin or far object is often centimetres off, while a
  // lost (hidden) object has seldom moved.
  bool contest_restarts = true;
  // Orientation search (orientation_search.hpp): when a track is confirmed, and when a lost track
  // restarts from a detection, it is refined briefly from its rotation turned by each of the 24
  // axis permutations of its box and goes on from the one the measurements support best.
  // For keypoint detectors, which confuse box corners (evaluate --detector and tracker.launch
  // with detector:=true turn it on). Off by default: on a nearly symmetric shape the search can
  // trade a right rotation for its near twin. Tentative tracks (mostly false positives) are not
  // searched: a search refines 24 candidates.
  bool search_orientations = false;
  int max_orientation_searches = 1;  // per frame (each refines 24 candidates): others wait a frame
  double orientation_search_interval_s = 2.0;  // a track is searched again no sooner than this
  // A confirmed track whose fit support stays below this is searched again (every
  // orientation_search_interval_s): a wrong turn explains fewer of its rays than the right one.
  // 0 turns it off.
  double research_below_fit_support = 0.9;
  // Near twins (registration/twin_evidence.hpp): the turns of a class's box under which its surface
  // lies within twin_max_surface_fraction of its diameter of itself, in the mean (the material
  // box, multimeter and relay turned by half a turn about their vertical axes). Every frame up to
  // twin_tests_per_frame confirmed, well-fitted tracks (in turn) weigh their pose against their
  // twins' on the depth; a track turns to a twin whose accumulated log odds (each frame's clipped
  // to twin_frame_cap, older ones kept by twin_retain per test) exceed twin_switch_log_odds.
  // 0 tests: off. (The surface fraction and the retained share are no parameters of the node.)
  int twin_tests_per_frame = 2;
  double twin_max_surface_fraction = 0.02;
  double twin_switch_log_odds = 12.0;
  double twin_frame_cap = 3.0;
  double twin_retain = 0.9;
  // Orientation disputes (tracking/track_lifecycle.hpp, OrientationDispute): a hypothesis turned
  // more than this from its track (up to symmetries) disputes the track's orientation; this many
  // in a row make the detection's pose compete with the track's (0: off).
  double orientation_dispute_deg = 30.0;
  int orientation_disputes = 3;
  // Position disputes (PositionDispute): this many hypotheses in a row placed beyond the 99.9 %
  // bound of the track's predicted position make the track's pose moved to the detection's
  // position compete with the track's (0: off).
  int position_disputes = 0;
  // A detection that restarts a track (its fit failed) outside the filter's 99.9 % gate replaces
  // the filter's belief instead of being averaged with it: an object turned in a hand is where
  // the detection sees it, not half-way.
  bool restart_replaces_outliers = true;
  // A detection associated with a track that it does not restart is a measurement of its pose
  // (hypothesis_sigma_m, hypothesis_sigma_rad) where it lies within the filter's 99.9 % gate:
  // the filter weighs it with the track's fits, so a far or small object whose depth barely
  // constrains its pose stays near what the detector sees.
  bool fuse_hypotheses = true;
  RefinerOptions orientation_refiner = orientationRefinerDefaults();
  bool run_presegmentation = true;
  bool compute_relations = true;
  relations::SceneRelationOptions relation_options;
  relations::HysteresisOptions relation_hysteresis;
  bool reparent = true;  // a track in / on another track becomes its child in the scene graph
  PipelineOptions() {
    refiner.full_resolution_last_round = false;  // pre-segmentation assigns every ray
    // A tracked object is mostly where its prediction puts it: its rounds stop once they move it
    // by less than a millimetre (doc/experiments.md section 43: suites unchanged, demo frame
    // 17-18 -> 13 ms).
    refiner.converged_step = 0.001;
  }

  static RefinerOptions orientationRefinerDefaults() {
    RefinerOptions o;
    o.rounds = 3;
    o.ray_stride = 2;
    o.full_resolution_last_round = false;
    o.max_dist_last = 0.02f;
    o.information = false;  // the contest compares pairs and residuals only
    return o;
  }
};

}  // namespace sgt
