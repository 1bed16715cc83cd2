#include "scene_graph_tracker/tracking/unlocated_tracks.hpp"

#include <algorithm>
#include <limits>

namespace sgt {

void UnlocatedTracks::add(const std::string& id, const std::string& class_name,
                          const Eigen::Vector3d& where, double stamp) {
  entries_.erase(
      std::remove_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.id == id; }),
      entries_.end());
  entries_.push_back(Entry{id, class_name, where, stamp, false});
}

std::string UnlocatedTracks::claim(const std::string& class_name, const Eigen::Vector3d& where) {
  Entry* best = nullptr;
  double best_d = std::numeric_limits<double>::infinity();
  for (Entry& e : entries_) {
    const double d = (e.where - where).norm();
    if (!e.claimed && e.class_name == class_name && d < best_d) best = &e, best_d = d;
  }
  if (!best) return {};
  best->claimed = true;
  return best->id;
}

void UnlocatedTracks::found(const std::string& id) {
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                [&](const Entry& e) { return e.id == id && e.claimed; }),
                 entries_.end());
}

void UnlocatedTracks::release(const std::string& id) {
  for (Entry& e : entries_)
    if (e.id == id) e.claimed = false;
}

void UnlocatedTracks::expire(double stamp, double keep_s) {
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                [&](const Entry& e) { return stamp - e.since > keep_s; }),
                 entries_.end());
}

}  // namespace sgt
