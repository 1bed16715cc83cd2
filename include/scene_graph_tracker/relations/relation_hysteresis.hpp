// Hysteresis on relation edges so the scene graph does not flicker: an edge appears after it held
// in `appear_frames` consecutive frames and disappears after it failed in `disappear_frames`.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene_graph_tracker/relations/scene_relations.hpp"

namespace sgt::relations {

struct HysteresisOptions {
  int appear_frames = 3;
  int disappear_frames = 5;
};

class RelationHysteresis {
 public:
  explicit RelationHysteresis(const HysteresisOptions& o = {}) : options_(o) {}
  // Feeds one frame's instantaneous edges; returns the stable edges after it.
  std::vector<Edge> update(const std::vector<Edge>& now);
  // Drops every edge naming `name` (a removed track) at once.
  void forget(const std::string& name);
  void clear() { state_.clear(); }
  void setOptions(const HysteresisOptions& o) { options_ = o; }

 private:
  struct State {
    int held = 0, missed = 0;
    bool shown = false;
  };
  HysteresisOptions options_;
  std::map<Edge, State> state_;
};

}  // namespace sgt::relations
