// The per-frame pipeline: localize -> associate hypotheses -> refine -> pre-segment. The offline
// evaluator and the ROS nodelet both feed it frames; neither re-implements any step.
//
// Frames: measurements arrive with their sensor poses in the odom frame (odometry). The pipeline
// keeps the map -> odom correction: it localizes the robot against the static map when a frame
// carries a LiDAR scan (or any sensor, see options), applies the correction to every sensor, and
// keeps it for the frames in between. Pose hypotheses (from a detector or the simulator) come in
// the base frame, are moved into the map with the corrected robot pose, and are assigned to the
// tracks of their class (Hungarian, gated by distance to the prediction); an unmatched hypothesis
// starts a tentative track. Every track is predicted by its Kalman filter (constant velocity),
// refined from the prediction, and updated with the refined pose when the refinement is good
// (otherwise it coasts on the prediction; a hypothesis re-initialises a track whose refinement
// failed). A track is removed only on evidence of absence: it should show points (its rays
// are not blocked by anything closer, known or unknown) yet gets no correspondences for
// remove_after_s; an occluded or out-of-view track just coasts.
//
// Relations: after refinement, the relations among confirmed tracks (confirmed or lost) and the
// static furniture (setFurniture) are computed (relations/scene_relations.hpp), held back by
// hysteresis (an edge shows after holding appear_frames frames, goes after failing
// disappear_frames) and returned as edges. With `reparent`, a track that is in or on another
// track becomes its child in the scene graph (world pose unchanged), and back under the world when
// that ends. A child is predicted with its parent: it keeps its pose relative to the parent, so
// a relay inside a carried KLT moves with it even while the KLT's walls hide it; a child gathers
// no evidence of absence (it goes when the relation ends and it is then seen missing).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/rigid.hpp"
#include "scene_graph_tracker/registration/localizer.hpp"
#include "scene_graph_tracker/registration/object_refiner.hpp"
#include "scene_graph_tracker/relations/relation_hysteresis.hpp"
#include "scene_graph_tracker/relations/scene_relations.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/scene/scene_graph.hpp"
#include "scene_graph_tracker/segmentation/presegmentation.hpp"
#include "scene_graph_tracker/tracking/pose_filter.hpp"

namespace sgt {

struct PoseHypothesis {
  std::string class_name;
  Eigen::Isometry3d T_base_object = Eigen::Isometry3d::Identity();
  double score = 1.0;
};

struct PipelineFrame {
  double stamp = 0.0;  // seconds
  Eigen::Isometry3d T_odom_base = Eigen::Isometry3d::Identity();
  // T_world_sensor of each set holds T_odom_sensor on input (odometry at the set's own stamp).
  std::vector<RangeMeasurements> measurements;
  std::vector<PoseHypothesis> hypotheses;
};

struct PipelineOptions {
  RefinerOptions refiner;
  LocalizerOptions localizer;
  PresegmentOptions presegmentation;
  PoseFilterNoise motion;
  bool localize = true;
  bool localize_with_lidar_only = true;  // depth images near a bench add little but cost rays
  // Whether tracked objects stay in the scene while the robot localizes (their points are then
  // explained and dropped). Off by default: the robot pose must not depend on object tracks,
  // which may be wrong exactly when the robot pose is (a track a few cm off hides the map
  // behind it); without them, points on objects are outliers that the threshold drops.
  bool localize_against_objects = false;
  // Objects are refined from the depth images of a frame; LiDAR returns (sparse, ~1 cm noise,
  // as much as a screwdriver's radius) only when the frame has no depth image or when this is set.
  bool refine_with_lidar = false;
  double min_hypothesis_score = 0.3;
  double association_distance = 0.15;  // m, hypothesis to a track's prediction (same class)
  double reacquire_distance = 0.6;     // m, for tracks that are not currently refined well
  int confirm_hits = 3;                // good refinements that confirm a tentative track ...
  // ... and detections associated with it (the one that started it counts). Refinement alone
  // confirmed a single false detection on an unknown box of about the right size, and the
  // confirmed track then explained the box's points (pre-segmentation recall 0.71 in the demo).
  int confirm_detections = 3;
  double confirm_inlier_ratio = 0.55;  // ... and whose fits explain at least this fraction of their rays
  // A tentative track's fit from fewer inliers than the refiner's alignment.min_points still
  // places the track when it has min_weak_fit_inliers and explains confirm_inlier_ratio of the
  // rays reaching the model: the next frame refines from there rather than from the detection
  // (it counts neither as a hit nor towards fit support). In the detector demo the screwdriver
  // at 2.6-2.8 m shows 5-15 rays and its detections are 7-15 cm off along its axis: each fit
  // got half way to it, and the next detection put the track back.
  int min_weak_fit_inliers = 6;
  // Fit support: the running mean (weight fit_support_weight per frame) of the inlier ratios of
  // a track's good fits, i.e. the share of the rays reaching its model that its measurements
  // agree with (the others pass through the model to something behind it). Confirmation needs
  // it at min_fit_support as well, so a few lucky fits among poor ones do not confirm; a
  // confirmed track below it collects evidence of absence and explains no points in
  // pre-segmentation. In the detector demo, models fitted to the walking person fell to
  // 0.3-0.5 within a second of being confirmed; real objects stayed at 0.75 and above
  // (0.59 for three frames of the multimeter right after it was confirmed).
  double fit_support_weight = 0.25;
  double min_fit_support = 0.65;
  // A track whose model lies partly inside the static map is nowhere a real object can be:
  // when more than max_sunk_fraction of its surface samples are deeper than sink_tolerance_m
  // behind the map's surface (its triangles' winding side), for remove_after_s, it goes, seen or
  // not. In the detector demo, false tracks sank 2-5 cm into the bench and the floor, where the
  // map hid them from every ray and no other evidence of absence reached them. Needs a map mesh
  // wound outwards (or towards where it was scanned from); 1 turns it off.
  double max_sunk_fraction = 0.2;
  double sink_tolerance_m = 0.01;
  double remove_after_s = 1.0;         // evidence of absence for this long removes a track
  double remove_tentative_after_s = 0.3;
  double tentative_timeout_s = 1.0;  // a tentative track without a hypothesis for this long goes
  double refined_sigma_m = 0.002, refined_sigma_rad = 0.01;        // refined pose noise
  int well_seen_points = 150;  // refinements with fewer inliers count as weaker measurements
  // Depth noise grows with range squared: a fit of an object farther than this from the sensor
  // counts as a weaker measurement, its covariance scaled by (range / far_fit_from_m)^4. At 2.8 m
  // the screwdriver's fits scatter by +-2 cm (depth sigma 12 mm); without it the filter followed
  // that scatter and its velocity carried the track 3 cm up when the object was hidden.
  double far_fit_from_m = 1.0;
  // Evidence of absence needs most of a confirmed object in view: when other tracked objects
  // cover more than this fraction of the rays that would reach it without them, the few rays
  // left (which graze the occluder and miss a track only a little off) are no evidence and the
  // track coasts.
  double max_hidden_fraction_for_absence = 0.5;
  // A lost track ignores fits farther than this from where it was lost, or explaining less than
  // this fraction of the rays that reach it, until a hypothesis restarts it (associate():
  // reacquire_distance); such fits are no evidence of absence either.
  double lost_track_max_jump_m = 0.03;
  double lost_track_resume_inlier_ratio = 0.8;
  double hypothesis_sigma_m = 0.02, hypothesis_sigma_rad = 0.08;   // detection noise
  // A detection restarts a lost track only when the measurements support it better than the
  // track's own pose: both are refined briefly (orientation_refiner), fits from too few points
  // scored too, and the detection must win by the search's own_margin with a fit explaining
  // confirm_inlier_ratio of its rays; a tie (nothing seen of either: a hidden object) keeps the
  // track. A track sunk into the static map (max_sunk_fraction) does not compete: nothing real is
  // there (workbench_alt: the multimeter, lost while the person reached over it, coasted 3 cm
  // down into the bench). In the detector demo the screwdriver at 2.5 m, lost for want of points
  // (5-15 rays), was put back 6-9 cm short along its axis by every detection, and half hidden by
  // the passing material box, dragged 4 cm towards the robot.
  bool contest_restarts = true;
  // Orientation search (orientation_search.hpp): when a track is confirmed, and when a lost track
  // restarts from a detection, it is refined briefly from its rotation turned by each of the 24
  // axis permutations of its box and goes on from the one the measurements support best.
  // For keypoint detectors, which confuse box corners (evaluate --detector and tracker.launch
  // with detector:=true turn it on). Off by default: with simulated hypotheses (2 deg noise) it
  // flipped the paper's nearly symmetric multimeter. Tentative tracks (mostly false positives)
  // are not searched: a search costs ~20 ms.
  bool search_orientations = false;
  int max_orientation_searches = 1;  // per frame (each refines 24 candidates): others wait a frame
  double orientation_search_interval_s = 2.0;  // a track is searched again no sooner than this
  // A confirmed track whose fit support stays below this is searched again (every
  // orientation_search_interval_s): a wrong turn explains fewer of its rays. In the detector demo
  // with scenario seed 44 the search at confirmation, 2.8 m away, turned the material box by 90 deg
  // about z; its fit support then stayed at 0.75-0.86 (right tracks: 0.95 and more), and it kept
  // that turn to the end (ADD-S 11 mm). 0 turns it off.
  double research_below_fit_support = 0.9;
  RefinerOptions orientation_refiner = orientationRefinerDefaults();
  bool run_presegmentation = true;
  bool compute_relations = true;
  relations::SceneRelationOptions relation_options;
  relations::HysteresisOptions relation_hysteresis;
  bool reparent = true;  // a track in / on another track becomes its child in the scene graph
  PipelineOptions() { refiner.full_resolution_last_round = false; }  // pre-segmentation assigns
  static RefinerOptions orientationRefinerDefaults() {
    RefinerOptions o;
    o.rounds = 3;
    o.ray_stride = 2;
    o.full_resolution_last_round = false;
    o.max_dist_last = 0.02f;
    return o;
  }
};

enum class TrackState { kTentative, kConfirmed, kLost, kRemoved };
const char* toString(TrackState s);

struct TrackedObject {
  NodeId node = kNoNode;
  std::string id;  // class + number, e.g. "klt_1"; never reused
  std::string class_name;
  std::string parent;  // id of the track it is in or on (its scene-graph parent); empty: the world
  Eigen::Isometry3d T_map_object = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();  // [t, R] of the filter
  TrackState state = TrackState::kTentative;
  ObjectQuality quality;  // of this frame's refinement
  double first_seen = 0.0, last_refined = 0.0, last_hypothesis = 0.0;
  int hits = 0;
  int detections = 0;  // hypotheses associated with the track (a track added by hand counts as confirmed)
};

struct StageTimes {
  double localize_ms = 0, associate_ms = 0, refine_ms = 0, presegment_ms = 0, total_ms = 0;
  // Not part of the pipeline (total_ms excludes it): the detector's time for the frame's RGB
  // image when the caller runs one (evaluate --detector); 0 otherwise.
  double detect_ms = 0;
  double relations_ms = 0;
};

struct PipelineResult {
  double stamp = 0.0;
  bool localized = false;
  LocalizeResult localization;
  Eigen::Isometry3d T_map_odom = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();
  std::vector<TrackedObject> objects;  // after refinement (removed tracks are not listed)
  std::vector<std::string> dropped;    // ids removed this frame
  std::vector<Presegmentation> presegmentation;  // per measurement set (empty when disabled)
  std::vector<RangeMeasurements> measurements;   // in the map frame, as used
  StageTimes times;
  std::vector<relations::Edge> relations;  // stable relation edges (after hysteresis)
};

class FramePipeline {
 public:
  FramePipeline(std::shared_ptr<const ObjectCatalog> catalog, std::shared_ptr<const TriangleMesh> static_map,
                const PipelineOptions& options = {});

  PipelineResult process(PipelineFrame frame);

  const PipelineOptions& options() const { return options_; }
  void setOptions(const PipelineOptions& o) { options_ = o; }
  const ObjectCatalog& catalog() const { return *catalog_; }
  const SceneGraph& graph() const { return graph_; }
  const RaycastScene& scene() const { return scene_; }
  const Eigen::Isometry3d& T_map_odom() const { return T_map_odom_; }
  void setMapOdom(const Eigen::Isometry3d& T) { T_map_odom_ = rigid(T); }
  // Tracks by hand (services): a tentative track of a catalog class at a map pose; its id.
  std::string addTrack(const std::string& class_name, const Eigen::Isometry3d& T_map_object, double stamp);
  bool removeTrack(const std::string& id);
  void reset();  // forget every track and the map -> odom correction
  NodeId mapNode() const { return map_node_; }
  // Static reference boxes for relations (e.g. relations::workbenchEntity(building)).
  void setFurniture(std::vector<relations::Entity> furniture) { furniture_ = std::move(furniture); }
  const std::vector<relations::Entity>& furniture() const { return furniture_; }

 private:
  struct Track {
    TrackedObject out;
    PoseFilter filter;
    double absent_since = -1.0;  // < 0: no evidence of absence
    double sunk_since = -1.0;    // < 0: not inside the static map
    double fit_support = -1.0;   // running mean of its good fits' inlier ratios (< 0: none yet)
    double last_orientation_search = -1e9;
    // A lost track's filter when a detection restarted it: contestRestarts() weighs its pose
    // against the detection's (a hidden object seldom moved; the detector's pose of a thin one is
    // often centimetres off).
    std::optional<PoseFilter> before_restart = std::nullopt;
  };
  void predict(double stamp);
  void setTracksEnabled(bool enabled);
  void associate(const std::vector<PoseHypothesis>& hypotheses, const Eigen::Isometry3d& T_map_base, double stamp);
  void updateTracks(const RefineResult& r, const std::vector<RangeMeasurements>& sets, double stamp,
                    std::vector<std::string>& dropped);
  // Whether the measurements show track k missing at its current pose in the scene (not where a
  // failed refinement drifted to): of the rays that reach its model, enough (min_points) and
  // most of those that would reach it without the other tracks (max_hidden_fraction_for_absence)
  // find no surface there (inlier ratio below the refiner's). frame_pipeline_visibility.cpp.
  bool seesAbsence(std::size_t k, const std::vector<RangeMeasurements>& sets);
  bool sunkIntoMap(const std::string& class_name, const Eigen::Isometry3d& T_map_object) const;  // max_sunk_fraction
  // In or on another track (a scene-graph child): it moves with its parent, which cuts its fits.
  bool isChild(NodeId node) const { return graph_.node(node).parent != kWorldNode; }
  // A track (not a child) whose recent fits the measurements contradict (fit support below
  // min_fit_support).
  bool unsupported(const Track& t) const {
    return !isChild(t.out.node) && t.fit_support >= 0.0 && t.fit_support < options_.min_fit_support;
  }
  // A tentative track (not a child) whose last fit had too few points but min_weak_fit_inliers
  // explaining confirm_inlier_ratio of its rays: that fit places it, and no detection resets it.
  bool placedByWeakFit(const Track& t) const {
    const ObjectQuality& q = t.out.quality;
    return !isChild(t.out.node) && t.out.state == TrackState::kTentative && q.status == RefineStatus::kTooFewPoints &&
           q.inliers >= options_.min_weak_fit_inliers && q.inlier_ratio >= options_.confirm_inlier_ratio;
  }
  // Covariance scale of a refined pose of track k: few inliers or far from the sensor.
  double fitWeakness(const TrackedObject& o, const std::vector<RangeMeasurements>& sets) const;
  void contestRestarts(const std::vector<RangeMeasurements>& sets);  // contest_restarts, for this frame's restarts
  // Of the tracks in needs_orientation_.
  void searchOrientations(const std::vector<RangeMeasurements>& sets, double stamp);
  std::vector<std::size_t> parentsFirst() const;  // track indices, every parent before its children
  std::string trackIdOf(NodeId node) const;       // "" when no track has that node
  void updateRelations(PipelineResult& out, const std::vector<RangeMeasurements>& sets);
  void reparent(const std::vector<relations::Edge>& edges);

  std::shared_ptr<const ObjectCatalog> catalog_;
  PipelineOptions options_;
  RaycastScene scene_;
  SceneGraph graph_;
  std::map<std::string, MeshId> class_mesh_;
  std::map<std::string, std::vector<Eigen::Vector3f>> class_samples_;  // surface points, object frame
  std::map<std::string, int> class_count_;
  std::vector<Track> tracks_;
  std::vector<std::string> needs_orientation_;  // track ids confirmed or restarted: search next
  double last_stamp_ = -1.0;
  Eigen::Isometry3d T_map_odom_ = Eigen::Isometry3d::Identity();
  NodeId map_node_ = kNoNode;
  std::vector<relations::Entity> furniture_;
  relations::RelationHysteresis hysteresis_;
};

}  // namespace sgt
