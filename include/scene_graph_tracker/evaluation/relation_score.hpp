// Scoring the tracker's relation edges against a scenario's declared relations, frame by frame.
//
// In a frame at scenario time t, with the evaluator's track -> object matching of that frame
// (tools/evaluate passes only confirmed or lost tracks, those in the scene graph, matched within
// 10 cm of the true position: a tracking failure is not a relation error):
//   - predicted edges are renamed to scenario ids (subject and object tracks matched to objects;
//     furniture names such as "workbench" stay); edges naming an unmatched track are not judged;
//   - a declaration is judged when its subject (and its object, unless furniture) is matched to a
//     track and t is not within `grace` seconds of its from / to: true positive when the renamed
//     edges hold it while it is active, false negative when they do not;
//   - a renamed edge whose kind is a declared kind and whose (subject, object) is a declared pair
//     (in any time window) but that no active declaration holds is a false positive, unless t is
//     within `grace` of a from / to of a declaration of the same edge.
// Precision = tp / (tp + fp), recall = tp / (tp + fn) over all frames. Edges of other kinds or
// between undeclared pairs are not judged (a scenario cannot list every true relation).
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene_graph_tracker/relations/scene_relations.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"

namespace sgt {

struct RelationCounts {
  std::size_t tp = 0, fp = 0, fn = 0;
  RelationCounts& operator+=(const RelationCounts& o) {
    tp += o.tp, fp += o.fp, fn += o.fn;
    return *this;
  }
};

struct RelationScoreOptions {
  double grace =
      0.5;  // s around each declared from / to that is not judged (hysteresis, approximate times)
};

// `t`: scenario time; `track_to_object`: track id -> scenario object id for this frame;
// `furniture`: names that are not tracks (kept as they are).
RelationCounts scoreRelations(double t, const std::vector<sim::RelationSpec>& declared,
                              const std::vector<relations::Edge>& predicted,
                              const std::map<std::string, std::string>& track_to_object,
                              const std::set<std::string>& furniture,
                              const RelationScoreOptions& o = {});

}  // namespace sgt
