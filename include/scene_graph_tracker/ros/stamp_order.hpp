// Whether a live frame's stamp may be processed after the last one. Frames must come in time
// order for the track filters: a duplicate stamp is dropped, a small step back (jitter between
// drivers or topics, up to max_jitter_s) is dropped without touching the tracks, and a real jump
// back (a bag played again, a clock reset) resets the tracks once and goes on from there.
#pragma once

#include <cmath>

namespace sgt::ros {

enum class StampVerdict { kProcess, kDuplicate, kJitter, kJumpBack };

class StampOrder {
 public:
  explicit StampOrder(double max_jitter_s = 1.0) : max_jitter_s_(max_jitter_s) {}
  // The verdict for `stamp` (seconds); kProcess and kJumpBack make it the last stamp.
  StampVerdict check(double stamp) {
    if (std::isnan(last_) || stamp > last_) return last_ = stamp, StampVerdict::kProcess;
    if (stamp == last_) return StampVerdict::kDuplicate;
    if (last_ - stamp <= max_jitter_s_) return StampVerdict::kJitter;
    last_ = stamp;
    return StampVerdict::kJumpBack;
  }
  void reset() { last_ = NAN; }

 private:
  double max_jitter_s_;
  double last_ = NAN;
};

}  // namespace sgt::ros
