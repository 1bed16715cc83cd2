// Pairs each RGB image with its registered depth image for the detector. The two streams arrive
// on different topics and are decoded by different callbacks (compressedDepth decodes slower than
// JPEG), so the depth image of an RGB image often arrives after it, more so on a loaded machine.
// An RGB image whose depth image may still come waits for it, at most `max_wait_s` of wall time;
// then its distances come from PnP alone, as when no depth image exists. It may still come while
// the depth stream is alive (a depth image arrived within the last second) and no buffered depth
// image is later than the image's stamp + max_offset (the streams are each in time order).
// One image waits at a time: a newer one ends the older one's wait. Thread-safe.
#pragma once

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <deque>
#include <mutex>
#include <optional>
#include <vector>

namespace sgt::ros {

struct RgbFrame {
  sensor_msgs::ImageConstPtr image;
  sensor_msgs::CameraInfoConstPtr info;
};

class DepthPairing {
 public:
  // max_offset_s: the most a depth image's stamp may differ from its RGB image's (s).
  // max_wait_s: how long an RGB image waits for its depth image (wall time; 0: never waits).
  DepthPairing(double max_offset_s, double max_wait_s, std::size_t keep = 5);

  // A depth image arrived. Returns the waiting RGB frame when this ends its wait (it matches, or
  // is later than its stamp + max_offset).
  std::optional<RgbFrame> addDepth(const sensor_msgs::ImageConstPtr& depth,
                                   const ::ros::WallTime& now);
  // An RGB frame arrived. Returns the frames to detect on now, in time order: an older waiting
  // one (its wait ended by this one), and this one unless it waits for its depth image.
  std::vector<RgbFrame> addImage(const RgbFrame& frame, const ::ros::WallTime& now);
  // The waiting frame once it has waited max_wait_s; nothing before that.
  std::optional<RgbFrame> expired(const ::ros::WallTime& now);
  // The buffered depth image closest to `stamp` within max_offset_s; null when there is none.
  sensor_msgs::ImageConstPtr closest(const ::ros::Time& stamp) const;
  double maxOffset() const { return max_offset_s_; }
  std::size_t waited() const;  // frames that waited, over the node's life

 private:
  bool mayStillCome(const ::ros::Time& stamp, const ::ros::WallTime& now) const;  // under mutex_

  const double max_offset_s_, max_wait_s_;
  const std::size_t keep_;
  mutable std::mutex mutex_;
  std::deque<sensor_msgs::ImageConstPtr> depth_;
  ::ros::WallTime last_depth_arrival_;
  std::optional<RgbFrame> waiting_;
  ::ros::WallTime waiting_since_;
  std::size_t waited_ = 0;
};

}  // namespace sgt::ros
