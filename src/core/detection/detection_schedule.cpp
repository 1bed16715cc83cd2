#include "scene_graph_tracker/detection/detection_schedule.hpp"

#include <algorithm>

namespace sgt::detection {
namespace {
// Image stamps at a frame rate do not add up exactly (15 x 1/30 s < 0.5 s).
constexpr double kStampTolerance = 1e-3;
}  // namespace

bool DetectionSchedule::due(double stamp, const cv::Mat& rgb) {
  const bool view = watchesView() && !rgb.empty();
  const bool run = !ran_ || stamp < last_run_ || stamp - last_run_ >= interval_ - kStampTolerance ||
                   (view && novelty_.share(rgb) >= options_.new_view_share);
  if (run) ran_ = true, last_run_ = stamp;
  if (run && view) novelty_.remember(rgb);
  return run;
}

double DetectionSchedule::lostSince(const std::string& id, double stamp) const {
  const auto it = gone_since_.find(id);
  return it != gone_since_.end() && it->second <= stamp ? it->second : stamp;
}

double DetectionSchedule::backedOff(double gone_s) const {
  return std::clamp(options_.lost_backoff * gone_s, options_.busy_interval_s,
                    std::max(options_.busy_interval_s, options_.settled_interval_s));
}

void DetectionSchedule::observe(double stamp, const std::vector<ScheduledTrack>& tracks) {
  std::map<std::string, double> gone_since;
  std::set<std::string> listed, known;
  bool busy = tracks.empty();
  for (const ScheduledTrack& t : tracks) {
    listed.insert(t.id);
    busy = busy || t.state == TrackState::kTentative;
    if (t.state != TrackState::kTentative) known.insert(t.id);
    if (t.state == TrackState::kLost) gone_since[t.id] = lostSince(t.id, stamp);
  }
  // A confirmed or lost track that is no longer listed was removed: gone from when it went.
  for (const std::string& id : known_)
    if (!listed.count(id)) gone_since[id] = lostSince(id, stamp);
  for (const auto& [id, since] : gone_since_)  // removed before: while it still asks for more
    if (!listed.count(id) && !gone_since.count(id) &&
        backedOff(stamp - since) < options_.settled_interval_s)
      gone_since[id] = since;
  interval_ = busy ? options_.busy_interval_s
                   : std::max(options_.busy_interval_s, options_.settled_interval_s);
  for (const auto& [id, since] : gone_since)
    interval_ = std::min(interval_, backedOff(stamp - since));
  gone_since_ = std::move(gone_since);
  known_ = std::move(known);
}

}  // namespace sgt::detection
