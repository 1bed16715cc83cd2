#include "scene_graph_tracker/relations/relation_hysteresis.hpp"

namespace sgt::relations {

std::vector<Edge> RelationHysteresis::update(const std::vector<Edge>& now) {
  const std::set<Edge> holding(now.begin(), now.end());
  for (const Edge& e : holding) state_[e];
  std::vector<Edge> shown;
  for (auto it = state_.begin(); it != state_.end();) {
    State& s = it->second;
    if (holding.count(it->first)) {
      ++s.held, s.missed = 0;
      if (s.held >= options_.appear_frames) s.shown = true;
    } else {
      ++s.missed, s.held = 0;
      if (s.missed >= options_.disappear_frames) s.shown = false;
    }
    if (!s.shown && s.held == 0) {
      it = state_.erase(it);
      continue;
    }
    if (s.shown) shown.push_back(it->first);
    ++it;
  }
  return shown;
}

void RelationHysteresis::forget(const std::string& name) {
  for (auto it = state_.begin(); it != state_.end();)
    it = it->first.subject == name || it->first.object == name ? state_.erase(it) : std::next(it);
}

}  // namespace sgt::relations
