#include "scene_graph_tracker/evaluation/track_figures.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "scene_graph_tracker/evaluation/json_number.hpp"

namespace sgt {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

struct PerTrack {
  std::string class_name;
  std::vector<double> inliers, ratio, residual_mm;
};

std::map<std::string, PerTrack> perTrack(const std::vector<TrackSample>& samples) {
  std::map<std::string, PerTrack> out;
  for (const TrackSample& s : samples) {
    if (!s.confirmed) continue;
    PerTrack& t = out[s.id];
    t.class_name = s.class_name;
    t.inliers.push_back(s.inliers), t.ratio.push_back(s.inlier_ratio);
    if (s.depth_residual_m) t.residual_mm.push_back(*s.depth_residual_m * 1000);
  }
  return out;
}

}  // namespace

std::string poseColumns(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d t = T.translation();
  const Eigen::Quaterniond q(T.rotation());
  std::ostringstream o;
  o << std::setprecision(9) << "," << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << ","
    << q.y() << "," << q.z() << "," << q.w();
  return o.str();
}

void TrackFigures::add(const TrackSample& s) { samples_.push_back(s); }

void TrackFigures::addFrame(double, std::size_t confirmed) {
  counts_.push_back(static_cast<double>(confirmed));
}

std::string TrackFigures::json(const std::string& in) const {
  std::ostringstream o;
  o << in << "\"tracks\": {\n"
    << in << "  \"frames\": " << counts_.size() << ",\n"
    << in << "  \"count_median\": " << jsonNumber(median(counts_)) << ",\n"
    << in << "  \"count_max\": "
    << jsonNumber(counts_.empty() ? NAN : *std::max_element(counts_.begin(), counts_.end()))
    << ",\n"
    << in << "  \"per_track\": {";
  bool first = true;
  for (const auto& [id, t] : perTrack(samples_)) {
    o << (first ? "\n" : ",\n") << in << "    \"" << id << "\": {\"class\": \"" << t.class_name
      << "\", \"frames\": " << t.inliers.size()
      << ", \"inliers_median\": " << jsonNumber(median(t.inliers))
      << ", \"inlier_ratio_median\": " << jsonNumber(median(t.ratio))
      << ", \"depth_residual_median_mm\": " << jsonNumber(median(t.residual_mm)) << "}";
    first = false;
  }
  o << (first ? "" : "\n" + in + "  ") << "}\n" << in << "}";
  return o.str();
}

std::string TrackFigures::markdown() const {
  const auto tracks = perTrack(samples_);
  if (tracks.empty()) return "";
  std::ostringstream o;
  o << std::fixed << std::setprecision(2) << "\nTracks (no ground truth needed): " << tracks.size()
    << " confirmed, " << median(counts_) << " per frame (median), at most "
    << *std::max_element(counts_.begin(), counts_.end()) << ".\n\n"
    << "| track | class | frames | fit support (median) | inlier ratio | depth residual mm |\n"
    << "|---|---|---|---|---|---|\n";
  for (const auto& [id, t] : tracks)
    o << "| " << id << " | " << t.class_name << " | " << t.inliers.size() << " | "
      << median(t.inliers) << " | " << median(t.ratio) << " | " << median(t.residual_mm) << " |\n";
  return o.str();
}

std::string TrackFigures::csvRows() const {
  std::ostringstream o;
  o << std::setprecision(15);
  for (const TrackSample& s : samples_)
    o << "track," << s.stamp << "," << s.id << "," << s.class_name << ",,,,,,,,,,,," << s.id << ","
      << (s.depth_residual_m ? jsonNumber(*s.depth_residual_m * 1000) : "") << ",," << s.inliers
      << "," << jsonNumber(s.inlier_ratio) << "," << (s.confirmed ? 1 : 0) << ","
      << poseColumns(s.T_map_object) << ",," << jsonNumber(s.orientation_confidence) << "\n";
  return o.str();
}

}  // namespace sgt
