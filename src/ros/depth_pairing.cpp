#include "scene_graph_tracker/ros/depth_pairing.hpp"

#include "scene_graph_tracker/ros/closest_in_time.hpp"

namespace sgt::ros {

namespace {
constexpr double kDepthStreamAliveS = 1.0;  // a depth image within this long: the stream is alive
}  // namespace

DepthPairing::DepthPairing(double max_offset_s, double max_wait_s, std::size_t keep)
    : max_offset_s_(max_offset_s), max_wait_s_(max_wait_s), keep_(keep) {}

std::optional<RgbFrame> DepthPairing::addDepth(const sensor_msgs::ImageConstPtr& depth,
                                               const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  pushRecent(depth_, depth, keep_);
  last_depth_arrival_ = now;
  if (!waiting_) return std::nullopt;
  const ::ros::Time& stamp = waiting_->image->header.stamp;
  if (mayStillCome(stamp, now) && !closestInTime(depth_, stamp, max_offset_s_)) return std::nullopt;
  std::optional<RgbFrame> done;
  done.swap(waiting_);
  return done;
}

std::vector<RgbFrame> DepthPairing::addImage(const RgbFrame& frame, const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<RgbFrame> now_ready;
  if (waiting_) now_ready.push_back(*waiting_), waiting_.reset();
  const ::ros::Time& stamp = frame.image->header.stamp;
  if (max_wait_s_ > 0.0 && !closestInTime(depth_, stamp, max_offset_s_) &&
      mayStillCome(stamp, now)) {
    waiting_ = frame, waiting_since_ = now, ++waited_;
  } else {
    now_ready.push_back(frame);
  }
  return now_ready;
}

std::optional<RgbFrame> DepthPairing::expired(const ::ros::WallTime& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!waiting_ || (now - waiting_since_).toSec() < max_wait_s_) return std::nullopt;
  std::optional<RgbFrame> done;
  done.swap(waiting_);
  return done;
}

sensor_msgs::ImageConstPtr DepthPairing::closest(const ::ros::Time& stamp) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closestInTime(depth_, stamp, max_offset_s_);
}

std::size_t DepthPairing::waited() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waited_;
}

bool DepthPairing::mayStillCome(const ::ros::Time& stamp, const ::ros::WallTime& now) const {
  if (depth_.empty() || (now - last_depth_arrival_).toSec() > kDepthStreamAliveS) return false;
  return (depth_.back()->header.stamp - stamp).toSec() <= max_offset_s_;
}

}  // namespace sgt::ros
