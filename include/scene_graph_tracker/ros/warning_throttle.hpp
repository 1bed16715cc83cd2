// Warnings about bad input at sensor rate: each distinct problem is logged at once, a repeated
// one at most every `period` seconds, so 30 Hz of broken frames neither floods the log nor hides
// a new kind of problem.
#pragma once

#include <ros/time.h>

#include <string>

namespace sgt::ros {

class WarningThrottle {
 public:
  explicit WarningThrottle(double period_s = 2.0) : period_(period_s) {}
  // True when `text` should be logged now.
  bool shouldLog(const std::string& text) {
    const ::ros::WallTime now = ::ros::WallTime::now();
    if (text == last_ && (now - last_time_).toSec() < period_) return false;
    last_ = text, last_time_ = now;
    return true;
  }

 private:
  double period_;
  std::string last_;
  ::ros::WallTime last_time_;
};

}  // namespace sgt::ros
