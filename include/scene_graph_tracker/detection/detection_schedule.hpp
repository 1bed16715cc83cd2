// When the keypoint detector runs on an image. A tracked object needs no detection: the
// refinement carries it from frame to frame. Detections start tracks, confirm them and find lost
// ones again. So the detector runs every `busy_interval_s` while there is no track or a track is
// tentative, and every `settled_interval_s` while every track is confirmed. A track that is lost,
// or was removed, asks for detections that grow rarer the longer it has been gone (a backoff):
// every max(busy, lost_backoff x time gone), up to the settled interval. An object that just went
// behind something or out of view is looked for often, one gone for good (or a false track that
// lingers) soon costs no more than the settled rate. Whatever the interval, an image of which at
// least `new_view_share` is new since the last detected one (the camera turned, something moved
// away or came closer: what is new has not been looked at; ViewNovelty) is detected. The same
// schedule runs in the detector nodelet (on the tracker's published tracks) and in `evaluate` (on
// the pipeline's). The detector's defaults keep it off (settled_interval 0: every image): with it
// on, the live Tiago rostest confirms false tracks that detections on every image avoid
// (doc/experiments.md section 39).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene_graph_tracker/detection/view_novelty.hpp"
#include "scene_graph_tracker/tracking/track_lifecycle.hpp"

namespace sgt::detection {

struct DetectionScheduleOptions {
  double busy_interval_s = 0.0;     // 0: every image
  double settled_interval_s = 0.0;  // 0: every image (no schedule)
  double lost_backoff = 0.25;       // s of interval per s gone
  double new_view_share = 0.0;      // 0: the view's changes do not matter
};

struct ScheduledTrack {
  std::string id;
  TrackState state = TrackState::kTentative;
};

class DetectionSchedule {
 public:
  explicit DetectionSchedule(const DetectionScheduleOptions& options = {}) : options_(options) {}

  // Whether the image stamped `stamp` (s) is to be detected; if so, it counts as the last run.
  // The first image, and one stamped before the last run (a time jump, a bag played again), are.
  // `rgb` (may be empty) is the image, for the share of it that is new (new_view_share).
  bool due(double stamp, const cv::Mat& rgb = cv::Mat());
  // The tracks after the frame stamped `stamp` (all of them: a track not listed is gone).
  void observe(double stamp, const std::vector<ScheduledTrack>& tracks);
  // The interval the tracks observed last ask for (s).
  double interval() const { return interval_; }
  bool settled() const { return interval_ >= options_.settled_interval_s; }
  // Whether due() looks at the image (new_view_share set): a caller may skip decoding it if not.
  bool watchesView() const { return options_.new_view_share > 0.0; }

 private:
  double lostSince(const std::string& id, double stamp) const;
  double backedOff(double gone_s) const;

  DetectionScheduleOptions options_;
  ViewNovelty novelty_;  // since the last run
  double interval_ = 0.0;
  double last_run_ = -1.0;
  bool ran_ = false;
  std::map<std::string, double> gone_since_;  // lost or removed tracks: since when
  std::set<std::string> known_;               // confirmed or lost in the last observation
};

}  // namespace sgt::detection
