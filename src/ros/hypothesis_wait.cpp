#include "scene_graph_tracker/ros/hypothesis_wait.hpp"

namespace sgt::ros {

namespace {
constexpr double kStreamAliveS = 1.0;  // an array within this long: the detector is running
}  // namespace

HypothesisWait::HypothesisWait(double max_wait_s, std::size_t keep)
    : max_wait_s_(max_wait_s), keep_(keep) {}

std::vector<DepthFrame> HypothesisWait::addDepth(const DepthFrame& frame,
                                                 const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<DepthFrame> ready;
  if (waiting_.empty() && !mayStillCome(frame.image->header.stamp, now)) {
    ready.push_back(frame);
    return ready;
  }
  waiting_.push_back({frame, now});
  ++waited_;
  while (waiting_.size() > keep_) release(ready, true);
  return ready;
}

std::vector<DepthFrame> HypothesisWait::addHypotheses(const ::ros::Time& stamp,
                                                      const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  any_hypotheses_ = true;
  last_stamp_ = stamp, last_arrival_ = now;
  std::vector<DepthFrame> ready;
  while (!waiting_.empty() && waiting_.front().frame.image->header.stamp <= stamp)
    release(ready, false);
  return ready;
}

std::vector<DepthFrame> HypothesisWait::expired(const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<DepthFrame> ready;
  while (!waiting_.empty() && (now - waiting_.front().since).toSec() >= max_wait_s_)
    release(ready, true);
  return ready;
}

std::size_t HypothesisWait::waited() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waited_;
}

std::size_t HypothesisWait::waitedInVain() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return in_vain_;
}

bool HypothesisWait::mayStillCome(const ::ros::Time& stamp, const ::ros::WallTime& now) const {
  return max_wait_s_ > 0.0 && any_hypotheses_ && (now - last_arrival_).toSec() <= kStreamAliveS &&
         last_stamp_ < stamp;
}

void HypothesisWait::release(std::vector<DepthFrame>& out, bool in_vain) {
  out.push_back(waiting_.front().frame);
  waiting_.pop_front();
  in_vain_ += in_vain;
}

}  // namespace sgt::ros
