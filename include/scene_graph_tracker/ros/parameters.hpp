// The nodelets' parameters through the parameter schema (pipeline/parameter_schema.hpp): read
// from the private namespace by name, and to and from dynamic_reconfigure, whose names are the
// schema's with '_' for '/' (params::reconfigureName).
#pragma once

#include <dynamic_reconfigure/Config.h>
#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "scene_graph_tracker/pipeline/parameter_schema.hpp"

namespace sgt::ros {

// Sets every parameter of `schema` that the private namespace of `pnh` holds; the others keep
// their value in `options`. Throws params::ParameterError naming the parameter when one has the
// wrong type or is out of range. Returns the names in the namespace that are no parameter of the
// schema (nor one's dynamic_reconfigure name), for a warning.
template <class Options>
std::vector<std::string> readParameters(const ::ros::NodeHandle& pnh,
                                        const params::Schema<Options>& schema, Options& options);

// Writes the values of the run-time parameters into `config` (a Config message from the generated
// Config type's __toMessage__, e.g. of its defaults). Throws params::ParameterError when `config`
// lacks one (cfg/Tracker.cfg out of date).
template <class Options>
void toReconfigure(const params::Schema<Options>& schema, const Options& options,
                   dynamic_reconfigure::Config& config);

// Sets the run-time parameters from `config` (what the reconfigure callback received, through
// __toMessage__). Throws params::ParameterError when one is missing or out of range.
template <class Options>
void fromReconfigure(const params::Schema<Options>& schema,
                     const dynamic_reconfigure::Config& config, Options& options);

}  // namespace sgt::ros
