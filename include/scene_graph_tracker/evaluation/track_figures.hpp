// Per-track figures that need no ground truth, so that a user's own bag gets a report: for each
// track in each frame, its fit support (measurements paired with it), inlier ratio and median depth
// residual on its visible surface (evaluation/surface_fit.hpp), its pose, and the number of tracks
// per frame. EvaluationReport writes them as report.json "tracks", a report.md table and "track"
// rows of timeseries.csv.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sgt {

struct TrackSample {
  double stamp = 0.0;
  std::string id, class_name;
  bool confirmed = false;  // confirmed or lost, not tentative
  int inliers = 0;         // fit support: measurements paired with the track in its refinement
  double inlier_ratio = 0.0;
  std::optional<double> depth_residual_m;  // nullopt: no visible pixel
  Eigen::Isometry3d T_map_object = Eigen::Isometry3d::Identity();
  double orientation_confidence = 1.0;  // TrackedObject::orientation_confidence
};

// The timeseries.csv pose columns x, y, z, qx, qy, qz, qw of `T`, each after a comma.
std::string poseColumns(const Eigen::Isometry3d& T);

class TrackFigures {
 public:
  void add(const TrackSample& s);
  // One frame ended with `confirmed` confirmed (or lost) tracks.
  void addFrame(double stamp, std::size_t confirmed);
  // The "tracks" key (without a trailing comma): count_median, count_max, frames and per_track
  // {id: {class, frames, inliers_median, inlier_ratio_median, depth_residual_median_mm}}.
  std::string json(const std::string& indent) const;
  std::string markdown() const;  // a table, one row per track (empty without tracks)
  // timeseries.csv rows of kind "track", in the columns of EvaluationReport::timeseriesCsv().
  std::string csvRows() const;

 private:
  std::vector<TrackSample> samples_;
  std::vector<double> counts_;
};

}  // namespace sgt
