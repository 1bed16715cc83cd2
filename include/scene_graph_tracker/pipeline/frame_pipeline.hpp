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
#include "scene_graph_tracker/pipeline/pipeline_options.hpp"
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
