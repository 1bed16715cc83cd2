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
    const StampVerdict v = peek(stamp);
    if (v == StampVerdict::kProcess || v == StampVerdict::kJumpBack) last_ = stamp;
    return v;
  }
  // The verdict without taking the stamp: a caller that may still reject the frame (no TF for
  // it) takes it with take() once the frame is good, so that one bad frame stamped far in the
  // future cannot make every later frame look like a jump back.
  StampVerdict peek(double stamp) const {
    if (std::isnan(last_) || stamp > last_) return StampVerdict::kProcess;
    if (stamp == last_) return StampVerdict::kDuplicate;
    if (last_ - stamp <= max_jitter_s_) return StampVerdict::kJitter;
    return StampVerdict::kJumpBack;
  }
  void take(double stamp) { last_ = stamp; }
  void reset() { last_ = NAN; }

 private:
  double max_jitter_s_;
  double last_ = NAN;
};

}  // namespace sgt::ros
