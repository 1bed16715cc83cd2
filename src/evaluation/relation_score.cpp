#include "scene_graph_tracker/evaluation/relation_score.hpp"

#include <cmath>
#include <tuple>

namespace sgt {
namespace {

bool nearBoundary(const sim::RelationSpec& d, double t, double grace) {
  return std::abs(t - d.from) < grace || std::abs(t - d.to) < grace;
}
bool sameEdge(const sim::RelationSpec& d, const relations::Edge& e) {
  return d.subject == e.subject && d.relation == e.relation && d.object == e.object;
}

}  // namespace

RelationCounts scoreRelations(double t, const std::vector<sim::RelationSpec>& declared,
                              const std::vector<relations::Edge>& predicted,
                              const std::map<std::string, std::string>& track_to_object,
                              const std::set<std::string>& furniture,
                              const RelationScoreOptions& o) {
  auto rename = [&](const std::string& name, std::string& out) {
    if (furniture.count(name)) return out = name, true;
    const auto it = track_to_object.find(name);
    if (it == track_to_object.end()) return false;
    out = it->second;
    return true;
  };
  std::vector<relations::Edge> renamed;
  for (const relations::Edge& e : predicted) {
    relations::Edge r = e;
    if (rename(e.subject, r.subject) && rename(e.object, r.object)) renamed.push_back(r);
  }
  std::set<std::string> tracked;
  for (const auto& [track, object] : track_to_object) tracked.insert(object);
  std::set<std::pair<std::string, std::string>> pairs;
  std::set<relations::Relation> kinds;
  for (const sim::RelationSpec& d : declared)
    pairs.emplace(d.subject, d.object), kinds.insert(d.relation);

  RelationCounts c;
  for (const sim::RelationSpec& d : declared) {
    const bool judged =
        tracked.count(d.subject) && (tracked.count(d.object) || furniture.count(d.object));
    if (!judged || !d.activeAt(t) || nearBoundary(d, t, o.grace)) continue;
    bool found = false;
    for (const relations::Edge& e : renamed) found = found || sameEdge(d, e);
    (found ? c.tp : c.fn) += 1;
  }
  for (const relations::Edge& e : renamed) {
    if (!kinds.count(e.relation) || !pairs.count({e.subject, e.object})) continue;
    bool active = false, near = false;
    for (const sim::RelationSpec& d : declared)
      if (sameEdge(d, e))
        active = active || d.activeAt(t), near = near || nearBoundary(d, t, o.grace);
    if (!active && !near) ++c.fp;
  }
  return c;
}

}  // namespace sgt
