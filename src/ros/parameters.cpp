#include "scene_graph_tracker/ros/parameters.hpp"

#include <ros/param.h>

#include <optional>
#include <set>

namespace sgt::ros {
namespace {

using params::ParameterError;
using params::Type;

template <class T>
std::optional<params::Value> get(const ::ros::NodeHandle& pnh, const std::string& name) {
  T v;
  if (!pnh.getParam(name, v)) return std::nullopt;
  return params::Value(v);
}

template <class Message>
const Message* entry(const std::vector<Message>& list, const std::string& name) {
  for (const Message& m : list)
    if (m.name == name) return &m;
  return nullptr;
}

template <class Message>
Message* entry(std::vector<Message>& list, const std::string& name) {
  for (Message& m : list)
    if (m.name == name) return &m;
  return nullptr;
}

ParameterError notInConfig(const std::string& name) {
  return ParameterError(name + ": not in dynamic_reconfigure as " + params::reconfigureName(name) +
                        " (cfg/Tracker.cfg out of date: make params)");
}

}  // namespace

template <class O>
std::vector<std::string> readParameters(const ::ros::NodeHandle& pnh,
                                        const params::Schema<O>& schema, O& options) {
  for (const params::Param<O>& p : schema) {
    if (!pnh.hasParam(p.name)) continue;
    // The same reads as NodeHandle::param (an int is read as a double too).
    const std::optional<params::Value> v = p.type == Type::kBool  ? get<bool>(pnh, p.name)
                                           : p.type == Type::kInt ? get<int>(pnh, p.name)
                                           : p.type == Type::kDouble
                                               ? get<double>(pnh, p.name)
                                               : get<std::string>(pnh, p.name);
    if (!v)
      throw ParameterError(pnh.resolveName(p.name) + ": not " +
                           (p.type == Type::kInt ? "an " : "a ") + params::toString(p.type));
    try {
      params::set(schema, options, p.name, *v);
    } catch (const ParameterError& e) {
      throw ParameterError(pnh.getNamespace() + "/" + e.what());
    }
  }
  std::set<std::string> known;
  for (const params::Param<O>& p : schema) known.insert({p.name, params::reconfigureName(p.name)});
  std::vector<std::string> names, unknown;
  ::ros::param::getParamNames(names);
  const std::string ns = pnh.getNamespace() + "/";
  for (const std::string& n : names)
    if (n.compare(0, ns.size(), ns) == 0 && !known.count(n.substr(ns.size())))
      unknown.push_back(n.substr(ns.size()));
  return unknown;
}

template <class O>
void toReconfigure(const params::Schema<O>& schema, const O& options,
                   dynamic_reconfigure::Config& config) {
  for (const params::Param<O>& p : schema) {
    if (!p.runtime) continue;
    const std::string name = params::reconfigureName(p.name);
    const params::Value v = p.get(options);
    if (p.type == Type::kBool) {
      auto* e = entry(config.bools, name);
      if (!e) throw notInConfig(p.name);
      e->value = std::get<bool>(v);
    } else if (p.type == Type::kInt) {
      auto* e = entry(config.ints, name);
      if (!e) throw notInConfig(p.name);
      e->value = std::get<int>(v);
    } else if (p.type == Type::kDouble) {
      auto* e = entry(config.doubles, name);
      if (!e) throw notInConfig(p.name);
      e->value = std::get<double>(v);
    } else {
      throw ParameterError(p.name + ": no run-time strings");
    }
  }
}

template <class O>
void fromReconfigure(const params::Schema<O>& schema, const dynamic_reconfigure::Config& config,
                     O& options) {
  for (const params::Param<O>& p : schema) {
    if (!p.runtime) continue;
    const std::string name = params::reconfigureName(p.name);
    std::optional<params::Value> v;
    if (p.type == Type::kBool) {
      if (const auto* e = entry(config.bools, name)) v = static_cast<bool>(e->value);
    } else if (p.type == Type::kInt) {
      if (const auto* e = entry(config.ints, name)) v = static_cast<int>(e->value);
    } else if (p.type == Type::kDouble) {
      if (const auto* e = entry(config.doubles, name)) v = static_cast<double>(e->value);
    }
    if (!v) throw notInConfig(p.name);
    params::set(schema, options, p.name, *v);
  }
}

#define SGT_INSTANTIATE(O)                                                                       \
  template std::vector<std::string> readParameters(const ::ros::NodeHandle&,                     \
                                                   const params::Schema<O>&, O&);                \
  template void toReconfigure(const params::Schema<O>&, const O&, dynamic_reconfigure::Config&); \
  template void fromReconfigure(const params::Schema<O>&, const dynamic_reconfigure::Config&, O&);
SGT_INSTANTIATE(params::TrackerParameters)
SGT_INSTANTIATE(params::DetectorParameters)
#undef SGT_INSTANTIATE

}  // namespace sgt::ros
