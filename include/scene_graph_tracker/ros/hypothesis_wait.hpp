// Holds each depth frame until the detector has passed its stamp, so that the frame is paired with
// the hypothesis array of its own image (ros/frame_assembler.hpp), whatever the machine's load.
// The detector publishes one array per RGB image once its inference is done, so the array of an
// image usually arrives after the depth image of the same instant; taken at once, the frame would
// get the array of an earlier image or none, depending on timing, and a replayed bag would give
// other tracks on every run. A frame waits while its array may still come: the hypothesis stream
// is alive (an array arrived within the last second) and no array stamped at or after the frame
// has arrived (no later array can be closer to it). It waits at most `max_wait_s` of wall time,
// and at most `keep` frames wait (the oldest goes on when one more comes). Frames go on in the
// order they came. Thread-safe.
#pragma once

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <deque>
#include <mutex>
#include <vector>

namespace sgt::ros {

struct DepthFrame {
  sensor_msgs::ImageConstPtr image;
  sensor_msgs::CameraInfoConstPtr info;
};

class HypothesisWait {
 public:
  // max_wait_s: how long a depth frame waits for its hypotheses (wall time; 0: never waits).
  explicit HypothesisWait(double max_wait_s, std::size_t keep = 10);

  // A depth frame arrived: the frames to process now, in order (perhaps it).
  std::vector<DepthFrame> addDepth(const DepthFrame& frame, const ::ros::WallTime& now);
  // A hypothesis array stamped `stamp` arrived (after the tracker took it in): the waiting frames
  // it ends the wait of.
  std::vector<DepthFrame> addHypotheses(const ::ros::Time& stamp, const ::ros::WallTime& now);
  // The frames that have waited max_wait_s.
  std::vector<DepthFrame> expired(const ::ros::WallTime& now);
  std::size_t waited() const;        // frames that waited, over the node's life
  std::size_t waitedInVain() const;  // ... and went on without their array (max_wait_s, keep)

 private:
  struct Waiting {
    DepthFrame frame;
    ::ros::WallTime since;
  };
  bool mayStillCome(const ::ros::Time& stamp, const ::ros::WallTime& now) const;  // under mutex_
  void release(std::vector<DepthFrame>& out, bool in_vain);                       // under mutex_

  const double max_wait_s_;
  const std::size_t keep_;
  mutable std::mutex mutex_;
  std::deque<Waiting> waiting_;
  bool any_hypotheses_ = false;
  ::ros::Time last_stamp_;  // of the latest hypothesis array
  ::ros::WallTime last_arrival_;
  std::size_t waited_ = 0, in_vain_ = 0;
};

}  // namespace sgt::ros
