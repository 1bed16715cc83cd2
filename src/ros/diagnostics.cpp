#include "scene_graph_tracker/ros/diagnostics.hpp"

#include <ros/time.h>

#include <cmath>
#include <cstdio>

namespace sgt::ros {

diagnostic_msgs::DiagnosticArray diagnostics(const std::string& node,
                                             const std::string& hardware_id, bool ok,
                                             const std::string& message, const Counters& counters) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "scene_graph_tracker: " + node, s.hardware_id = hardware_id;
  s.level = ok ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
  s.message = message;
  for (const auto& [key, v] : counters) {
    diagnostic_msgs::KeyValue kv;
    char text[64];
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15)
      std::snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
    else
      std::snprintf(text, sizeof text, "%.6g", v);
    kv.key = key, kv.value = text;
    s.values.push_back(kv);
  }
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ::ros::Time::now();
  array.status.push_back(s);
  return array;
}

}  // namespace sgt::ros
