// Small buffers of recent messages, and the one closest in time to a stamp within a maximum
// offset: pairing a frame with the detections of its image (tracker) or an RGB image with its
// depth image (detector).
#pragma once

#include <ros/time.h>

#include <cmath>
#include <cstddef>
#include <utility>

namespace sgt::ros {

// `messages`: a container of message pointers with a header; null when none is within max_offset_s.
template <typename Container>
typename Container::value_type closestInTime(const Container& messages, const ::ros::Time& stamp,
                                             double max_offset_s) {
  typename Container::value_type best;
  double best_offset = max_offset_s;
  for (const auto& m : messages) {
    const double offset = std::abs((m->header.stamp - stamp).toSec());
    if (offset <= best_offset && (!best || offset < best_offset)) best = m, best_offset = offset;
  }
  return best;
}

// Appends `message` and drops the oldest beyond `keep`.
template <typename Container>
void pushRecent(Container& messages, typename Container::value_type message, std::size_t keep) {
  messages.push_back(std::move(message));
  while (messages.size() > keep) messages.pop_front();
}

}  // namespace sgt::ros
