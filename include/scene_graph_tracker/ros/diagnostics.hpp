// One node's health on /diagnostics: a status named "scene_graph_tracker: <node>", OK or WARN with
// a message, and its counters as key/value pairs (integers printed without decimals).
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>

#include <string>
#include <utility>
#include <vector>

namespace sgt::ros {

using Counters = std::vector<std::pair<std::string, double>>;

diagnostic_msgs::DiagnosticArray diagnostics(const std::string& node,
                                             const std::string& hardware_id, bool ok,
                                             const std::string& message, const Counters& counters);

}  // namespace sgt::ros
