// The per-frame pipeline, the paper's stages in order: localize the robot against the static map,
// predict the tracks and associate the pose hypotheses with them, refine every track by ray
// casting, advance each track's life cycle (tracking/track_lifecycle.hpp), compute relations and
// re-parent, pre-segment the measurements. The offline evaluator and the ROS nodelet both feed it
// frames; neither re-implements any step.
//
// Frames: measurements arrive with their sensor poses in the odom frame. The pipeline keeps the
// map -> odom correction from localization and applies it to every sensor. Hypotheses come in the
// base frame and are moved into the map with the corrected robot pose. Each track has a
// constant-velocity Kalman filter; a child in the scene graph (in or on another track) is
// predicted with its parent, keeping its pose relative to it.
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
#include "scene_graph_tracker/registration/twin_evidence.hpp"
#include "scene_graph_tracker/relations/relation_hysteresis.hpp"
#include "scene_graph_tracker/relations/scene_relations.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/scene/scene_graph.hpp"
#include "scene_graph_tracker/segmentation/presegmentation.hpp"
#include "scene_graph_tracker/tracking/pose_filter.hpp"
#include "scene_graph_tracker/tracking/track_lifecycle.hpp"
#include "scene_graph_tracker/tracking/unlocated_tracks.hpp"

namespace sgt {

struct PoseHypothesis {
  std::string class_name;
  Eigen::Isometry3d T_base_object = Eigen::Isometry3d::Identity();
  double score = 1.0;
  // The pose is known only up to the half turns of the class's box about its centre (a cuboid
  // keypoint detector: the corners have no labels that tell a box from its turns). The tracker
  // then takes, of those turns, the one nearest the track it is associated with.
  bool up_to_box_half_turns = false;
};

struct PipelineFrame {
  double stamp = 0.0;  // seconds
  Eigen::Isometry3d T_odom_base = Eigen::Isometry3d::Identity();
  // T_world_sensor of each set holds T_odom_sensor on input (odometry at the set's own stamp).
  std::vector<RangeMeasurements> measurements;
  std::vector<PoseHypothesis> hypotheses;
};

struct TrackedObject {
  NodeId node = kNoNode;
  std::string id;  // class + number, e.g. "klt_1"; never reused
  std::string class_name;
  std::string parent;  // id of the track it is in or on (its scene-graph parent); empty: the world
  Eigen::Isometry3d T_map_object = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance =
      Eigen::Matrix<double, 6, 6>::Identity();  // [t, R] of the filter
  TrackState state = TrackState::kTentative;
  ObjectQuality quality;  // of this frame's refinement
  double first_seen = 0.0, last_refined = 0.0, last_hypothesis = 0.0;
  int hits = 0;        // good fits that counted towards confirmation
  int detections = 0;  // hypotheses associated with it (a track added by hand counts as confirmed)
  // How sure its orientation is against its near twins (TwinBelief::confidence): 1 for a class
  // without twins or with twin tests off, 1 / (1 + twins) before any evidence.
  double orientation_confidence = 1.0;
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
  RangeNoise noise;  // the sensors' noise this frame was processed with (measured or configured)
  std::vector<TrackedObject> objects;  // after refinement (removed tracks are not listed)
  std::vector<std::string> dropped;    // ids removed this frame
  // Hypotheses left out by max_hypotheses_per_frame, max_tracks or max_tracks_per_class.
  std::size_t hypotheses_over_limits = 0;
  // Hypotheses no track took that overlap another of their class this frame, one that a track took
  // or that started a track (two objects cannot share a place): duplicates, which start no track.
  std::size_t hypotheses_duplicate = 0;
  std::vector<Presegmentation> presegmentation;  // per measurement set (empty when disabled)
  std::vector<RangeMeasurements> measurements;   // in the map frame, as used
  StageTimes times;
  std::vector<relations::Edge> relations;  // stable relation edges (after hysteresis)
};

// The life-cycle options among the pipeline's.
LifecycleOptions lifecycleOptions(const PipelineOptions& options);

class FramePipeline {
 public:
  FramePipeline(std::shared_ptr<const ObjectCatalog> catalog,
                std::shared_ptr<const TriangleMesh> static_map,
                const PipelineOptions& options = {});

  PipelineResult process(PipelineFrame frame);

  const PipelineOptions& options() const { return options_; }
  void setOptions(const PipelineOptions& o);  // a changed noise setting restarts its measurement
  const ObjectCatalog& catalog() const { return *catalog_; }
  const SceneGraph& graph() const { return graph_; }
  const RaycastScene& scene() const { return scene_; }
  const Eigen::Isometry3d& T_map_odom() const { return T_map_odom_; }
  void setMapOdom(const Eigen::Isometry3d& T) { T_map_odom_ = rigid(T); }
  // Tracks by hand (services): a tentative track of a catalog class at a map pose; its id.
  std::string addTrack(const std::string& class_name, const Eigen::Isometry3d& T_map_object,
                       double stamp);
  bool removeTrack(const std::string& id);
  void reset();  // forget every track and the map -> odom correction (ids keep counting)
  // The last number given to each class's tracks ("klt" -> 3: klt_3 is the newest id).
  const std::map<std::string, int>& lastTrackNumbers() const { return class_count_; }
  // Continues numbering after these (never below what this pipeline gave already), e.g. from a
  // previous run (ros/track_id_store.hpp).
  void continueTrackNumbers(const std::map<std::string, int>& last);
  NodeId mapNode() const { return map_node_; }
  // Static reference boxes for relations (e.g. relations::workbenchEntity(building)).
  void setFurniture(std::vector<relations::Entity> furniture) { furniture_ = std::move(furniture); }
  const std::vector<relations::Entity>& furniture() const { return furniture_; }

 private:
  // A track under `id` (empty: the class's next number); the rest as addTrack.
  std::string startTrack(const std::string& class_name, const Eigen::Isometry3d& T_map_object,
                         double stamp, const std::string& id);
  struct Track {
    TrackedObject out;  // pose and quality; its life-cycle fields are filled from `life` on output
    TrackLife life;
    PoseFilter filter;
    // A lost track's filter when a detection restarted it: the restart contest weighs its pose
    // against the detection's.
    std::optional<PoseFilter> before_restart = std::nullopt;
    // The pose the latest detection proposes once detections contest the track's orientation
    // (OrientationDispute: the detection's pose) or position (PositionDispute: the track's pose
    // moved to the detection's position, whose orientation is then searched if it wins).
    struct Contest {
      Eigen::Isometry3d pose;
      bool search_orientation = false;
    };
    std::optional<Contest> contested_by = std::nullopt;
    TwinBelief twins = TwinBelief{};  // evidence for its near twins (twin_tests_per_frame)
  };
  // Stages of process().
  void localize(PipelineFrame& frame, PipelineResult& out);
  // The depth noise of this frame's images (measure_depth_noise), folded into noise_.
  void measureNoise(const std::vector<RangeMeasurements>& sets);
  // `r` with the sensors' noise (noise_) and the noise_sigmas of the track refiner's options.
  RefinerOptions withSensorNoise(RefinerOptions r) const;
  std::vector<RangeMeasurements> localizationSets(const std::vector<RangeMeasurements>& sets) const;
  std::vector<RangeMeasurements> objectSets(const std::vector<RangeMeasurements>& sets) const;
  std::vector<PoseHypothesis> acceptedHypotheses(const std::vector<PoseHypothesis>& hypotheses,
                                                 std::size_t& over_limit) const;
  bool roomForTrack(const std::string& class_name) const;  // max_tracks, max_tracks_per_class
  void predict(double stamp);
  // out: T_map_base in, hypothesis counts out.
  void associate(const std::vector<PoseHypothesis>& hypotheses, double stamp, PipelineResult& out);
  // Whether hypothesis h lies within half its class's smallest box side of one in `placed` (this
  // frame's detections that a track took or started) of its class: the two would overlap, so they
  // are one object detected twice.
  bool overlapsPlaced(const std::vector<PoseHypothesis>& hypotheses,
                      const std::vector<Eigen::Isometry3d>& in_map,
                      const std::vector<std::size_t>& placed, std::size_t h) const;
  void refineTracks(const std::vector<RangeMeasurements>& sets, double stamp,
                    std::vector<std::string>& dropped);
  void updateRelations(PipelineResult& out, const std::vector<RangeMeasurements>& sets);
  std::vector<Presegmentation> presegmentAll(const std::vector<RangeMeasurements>& sets);
  std::vector<TrackedObject> snapshot() const;

  // Association (frame_pipeline_association.cpp).
  Eigen::MatrixXd associationCosts(const std::vector<PoseHypothesis>& hypotheses,
                                   const std::vector<Eigen::Isometry3d>& in_map,
                                   double forbidden) const;
  void restartFromDetection(Track& t, const Eigen::Isometry3d& T_map_object);
  // Of T_detected and its box half turns, the pose whose rotation lies nearest track t's (up to the
  // class's symmetries).
  Eigen::Isometry3d nearestBoxHalfTurn(const Track& t, const Eigen::Isometry3d& T_detected) const;

  // Life cycle (frame_pipeline_lifecycle.cpp): apply this frame's fits to the filters, gather the
  // evidence that needs the scene, advance every track, remove those that go.
  void updateTracks(const RefineResult& r, const std::vector<RangeMeasurements>& sets, double stamp,
                    std::vector<std::string>& dropped);
  TrackEvidence applyFit(std::size_t k, const ObjectEstimate& fit,
                         const std::vector<RangeMeasurements>& sets, double stamp,
                         const LifecycleOptions& lo);
  // Tracks that go (remove[k]) after being confirmed leave their ids waiting (unlocated_); a
  // track that claimed one and is confirmed found its object.
  void noteUnlocated(const std::vector<bool>& remove, double stamp);
  // TurnGate on this frame's fit (e.fit) at T_fit.
  bool turnedBeyondGate(const Track& t, const TrackEvidence& e, const Eigen::Isometry3d& T_fit,
                        const LifecycleOptions& lo) const;
  void gatherSceneEvidence(std::vector<TrackEvidence>& evidence, const std::vector<FitUse>& uses,
                           const std::vector<std::size_t>& order,
                           const std::vector<RangeMeasurements>& sets);
  // Each tentative track whose good fit this frame explains confirm_inlier_ratio of its rays: how
  // much its model adds to what the scene explains (TrackEvidence::presence), when
  // confirm_presence_score asks for it.
  void weighPresence(std::vector<TrackEvidence>& evidence, const std::vector<FitUse>& uses,
                     const std::vector<RangeMeasurements>& sets);
  void dropTrack(std::size_t k);
  LifecycleOptions lifecycleOptions() const { return sgt::lifecycleOptions(options_); }
  void setTracksEnabled(bool enabled);

  // What the measurements show of track k at its current pose in the scene. Missing: enough
  // rays reach its model (min_points) and most of them pass through where its surface should be
  // (measured beyond it; those measured before it within absence_noise_sigmas count against).
  // Hidden: too few rays reach it. There: otherwise. frame_pipeline_visibility.cpp.
  // `agreement` (when given): the share of those rays that agree with the model, or -1 when too
  // few reach it.
  Sighting sight(std::size_t k, const std::vector<RangeMeasurements>& sets,
                 double* agreement = nullptr);
  // Track k, seen absent where it coasts or out of view, dropped straight down (world -z) by up to
  // unseen_drop_m onto what lies below it: when the sensors cannot see it missing there (it went
  // down into a container, behind a wall), it stays there with a restarted filter. Returns
  // whether it moved. frame_pipeline_visibility.cpp.
  bool dropsOutOfSight(std::size_t k, const std::vector<RangeMeasurements>& sets);
  bool sunkIntoMap(const std::string& class_name,
                   const Eigen::Isometry3d& T_map_object) const;  // max_sunk_fraction
  // In or on another track (a scene-graph child): it moves with its parent, which cuts its fits.
  bool isChild(NodeId node) const { return graph_.node(node).parent != kWorldNode; }
  bool unsupported(const Track& t) const;      // FitSupport::unsupported
  bool placedByWeakFit(const Track& t) const;  // WeakFitPlacement, from its last fit
  // Covariance scale of a refined pose of track k: few inliers or far from the sensor.
  double fitWeakness(const TrackedObject& o, const std::vector<RangeMeasurements>& sets) const;
  void contestRestarts(
      const std::vector<RangeMeasurements>& sets);  // RestartContest, this frame's restarts
  // Tracks whose orientation detections contest: the detection's pose against the track's.
  void settleDisputes(const std::vector<RangeMeasurements>& sets, double stamp);
  void fuseOrDispute(Track& t, const Eigen::Isometry3d& T_detected);
  void noteDispute(Track& t, const Eigen::Isometry3d& T_detected);
  // Up to twin_tests_per_frame confirmed tracks (in turn) weigh their near twins; a track turns
  // to one the evidence has come to favour. frame_pipeline_twins.cpp.
  void weighTwins(const std::vector<RangeMeasurements>& sets);
  void turnToTwin(Track& t, const Eigen::Isometry3d& T_map_object);
  const std::vector<Eigen::Isometry3d>& twinsOf(const std::string& class_name);
  // Of the tracks in needs_orientation_.
  void searchOrientations(const std::vector<RangeMeasurements>& sets, double stamp);
  std::vector<std::size_t> parentsFirst() const;  // track indices, every parent before its children
  std::string trackIdOf(NodeId node) const;       // "" when no track has that node
  void reparent(const std::vector<relations::Edge>& edges);

  std::shared_ptr<const ObjectCatalog> catalog_;
  PipelineOptions options_;
  RaycastScene scene_;
  SceneGraph graph_;
  std::map<std::string, MeshId> class_mesh_;
  std::map<std::string, std::vector<Eigen::Vector3f>>
      class_samples_;  // surface points, object frame
  std::map<std::string, int> class_count_;
  std::vector<Track> tracks_;
  std::vector<std::string> needs_orientation_;  // track ids confirmed or restarted: search next
  std::map<std::string, std::vector<Eigen::Isometry3d>> class_twins_;  // near twins, by class
  std::size_t twin_cursor_ = 0;  // the next track whose twins are weighed
  double last_stamp_ = -1.0;
  Eigen::Isometry3d T_map_odom_ = Eigen::Isometry3d::Identity();
  RangeNoise noise_;  // the configured noise, then what the frames measure
  NodeId map_node_ = kNoNode;
  std::vector<relations::Entity> furniture_;
  relations::RelationHysteresis hysteresis_;
  UnlocatedTracks unlocated_;  // ids of tracks seen missing, waiting for their objects
};

}  // namespace sgt
