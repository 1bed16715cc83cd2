// Accumulates per-frame results of the pipeline against ground truth and writes the evaluation
// report: report.json (keys documented in the README: frames, objects.* (with false positives),
// hypotheses.* (when any were scored), localization.*, presegmentation.*, sensors.*, relations.*
// (when relations were scored), tracks.* (no ground truth needed), timing.*), report.md (tables)
// and timeseries.csv (one row per frame, object, false positive and track, read by
// scripts/plot_report.py).
#pragma once

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene_graph_tracker/evaluation/pose_metrics.hpp"
#include "scene_graph_tracker/evaluation/relation_score.hpp"
#include "scene_graph_tracker/evaluation/track_figures.hpp"
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

namespace sgt {

struct UnknownLabelCounts {
  std::size_t tp = 0, fp = 0, fn = 0;  // "unknown" against the truth "not in the catalog or map"
  std::size_t lidar_valid = 0, lidar_unknown = 0;
};

class EvaluationReport {
 public:
  void addFrame(double stamp, const StageTimes& times);
  // One ground-truth object in one frame: the track matched to it and its errors, or nullopt when
  // the pipeline had no estimate. A change of the matched track id is an identity switch. An
  // object outside the camera's view (`in_view` false: its centre does not project into the
  // image) is counted as out_of_view and not scored: nothing can see it move (an object picked up
  // while the robot looks away). Occluded objects in view are scored.
  void addObject(double stamp, const std::string& truth_id, const std::string& class_name,
                 const std::string& track_id, const std::optional<PoseErrors>& errors,
                 bool in_view = true);
  // A track in the scene graph (confirmed or lost) that no true object was matched to in this
  // frame: a false positive in the CLEAR-MOT sense (a track on a distractor or a person, a
  // duplicate, one far from its object).
  void addFalsePositive(double stamp, const std::string& track_id, const std::string& class_name);
  // One true object in view in one frame against the pose hypotheses of its class (the
  // detector's, or the bag's simulated ones): the errors of the nearest one within the
  // association gate, or nullopt when none was that close. hypotheses.* says how often the source
  // gave the tracker a start and how good that start was. `box_turn_deg`: for a hypothesis known
  // only up to its box's half turns (PoseHypothesis::up_to_box_half_turns), its rotation error
  // under the nearest turn (NaN otherwise): what the detector gets wrong beyond what it declares.
  void addHypothesis(const std::string& truth_id, const std::optional<PoseErrors>& nearest,
                     double box_turn_deg = NAN);
  // How well the matched track's pose (`tracked_m`) and the true pose (`given_m`) explain the
  // depth image on the object's visible surface (evaluation/surface_fit.hpp): the median
  // |measured - rendered depth|, for the object's row of the frame at `stamp` (ignored when
  // addObject gave it none). objects.depth_residual_median_mm and
  // objects.gt_depth_residual_median_mm are their medians. `alone_m`: what the mesh alone reaches
  // from the track's pose (SurfaceFitter::fitAlone); with it,
  // objects.depth_residual_alone_median_mm and objects.depth_residual_excess_max_mm (the most the
  // track's residual exceeded it in a frame).
  void addSurfaceFit(double stamp, const std::string& truth_id, std::optional<double> tracked_m,
                     std::optional<double> given_m, std::optional<double> alone_m = std::nullopt);
  void addLocalization(double stamp, double translation_m, double rotation_deg);
  // The depth noise a frame was processed with (PipelineResult::noise): its median over the frames
  // is sensors.depth_sigma_at_1m_median.
  void addDepthNoise(double sigma_at_1m) { depth_sigma_at_1m_.push_back(sigma_at_1m); }
  void addPresegmentation(const UnknownLabelCounts& counts);
  // One frame's relation counts (evaluation/relation_score.hpp); `declared`: declarations in the
  // scenario.
  void addRelations(const RelationCounts& counts, std::size_t declared);

  // Per-track figures without ground truth (evaluation/track_figures.hpp).
  TrackFigures& tracks() { return tracks_; }

  std::size_t frames() const { return frames_.size(); }
  std::string json() const;
  std::string markdown() const;
  std::string timeseriesCsv() const;

 private:
  std::string falsePositivesJson() const;  // the objects.false_* keys, each after a ",\n"
  std::string hypothesesJson() const;  // the hypotheses key with its trailing ",\n" (or nothing)
  std::string hypothesesMarkdown() const;
  std::string surfaceMarkdown() const;  // the depth residual table (or nothing)
  struct ObjectRow {
    double stamp;
    std::string id, class_name;
    std::optional<PoseErrors> e;
    bool in_view = true;
    std::string track;  // the track matched to the object ("" when none)
    std::optional<double> depth_residual_m, gt_depth_residual_m, alone_depth_residual_m;
  };
  struct FrameRow {
    double stamp;
    StageTimes times;
    std::optional<double> loc_t, loc_r;
  };
  std::vector<FrameRow> frames_;
  std::vector<double> depth_sigma_at_1m_;
  std::vector<ObjectRow> objects_;
  struct FalsePositiveRow {
    double stamp;
    std::string track_id, class_name;
  };
  std::vector<FalsePositiveRow> false_positives_;
  UnknownLabelCounts labels_;
  RelationCounts relations_;
  std::size_t relation_frames_ = 0, declared_relations_ = 0;
  struct HypothesisCounts {
    std::size_t evaluated = 0, found = 0;
    std::vector<double> t_mm, r_deg, r_box_deg;  // of the found ones
  };
  std::map<std::string, HypothesisCounts> hypotheses_;  // per truth id
  std::map<std::string, std::string> last_track_;       // truth id -> last matched track id
  std::map<std::string, int> switches_;
  TrackFigures tracks_;
};

}  // namespace sgt
