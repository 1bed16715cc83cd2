// The tracker's and the detector's parameters, each declared once (src/core/pipeline/
// parameter_schema.cpp): name, group, range, unit, one line of doc, whether it can change at run
// time, and the option field it sets. Type and default are the field's own: the default is read
// from a default-constructed option struct, so it is written only there.
//
// Names are the keys of config/tracker.yaml and config/detector.yaml and of the nodelets' private
// parameters; '/' nests (refine/rounds is `refine: {rounds: ...}` in YAML). dynamic_reconfigure
// names cannot hold '/': there a name is the same with '_' for '/' (refine_rounds, see
// reconfigureName). config/*.yaml, cfg/Tracker.cfg and the README's parameter tables are
// generated from the schema (tools/print_parameters.cpp, `make params`); test_parameter_schema
// fails when a committed copy differs.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "scene_graph_tracker/detection/cuboid_pnp.hpp"
#include "scene_graph_tracker/detection/detection_schedule.hpp"
#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "scene_graph_tracker/pipeline/pipeline_options.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt::params {

enum class Type { kBool, kInt, kDouble, kString };
const char* toString(Type t);
using Value = std::variant<bool, int, double, std::string>;

// An unknown name, a value of the wrong type or out of range; the message names the parameter.
class ParameterError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Group {
  const char* name;
  const char* doc;
};
// Every group, in the order of the generated files and tables.
const std::vector<Group>& groups();

template <class Options>
struct Param {
  std::string name;
  std::string group;
  Type type = Type::kBool;
  bool single = false;      // a float field: values are rounded to float
  double min = 0, max = 0;  // inclusive; numbers only
  std::string unit;
  std::string doc;       // one line, no quotes (dynamic_reconfigure refuses them)
  bool runtime = false;  // also in dynamic_reconfigure
  bool in_file = true;   // in config/*.yaml (false: paths, which the launch files set)
  std::function<Value(const Options&)> get;
  std::function<void(Options&, const Value&)> set;  // the value has the parameter's type
};
template <class Options>
using Schema = std::vector<Param<Options>>;

// The tracker nodelet's own parameters (group "node"; `evaluate` has flags for the paths).
struct TrackerNodeOptions {
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  bool publish_map_odom = true;
  // own: ray-cast localization against the static map; external: map -> odom from TF (amcl).
  std::string localization = "own";
  bool publish_object_tf = false;
  double hypothesis_max_age = 0.1;
  double hypothesis_max_wait = 0.3;     // s, wall time (ros/hypothesis_wait.hpp)
  double max_time_jitter = 1.0;         // s (ros/stamp_order.hpp)
  std::string depth_transport = "raw";  // raw, compressed, compressedDepth (ros/image_input.hpp)
  std::string static_map;               // required: the static world as a mesh or URDF
  std::string furniture;  // optional: named boxes for relations (relations/furniture.hpp)
  std::string catalog = "package://scene_graph_tracker/config/objects.yaml";
  std::string mesh_dir;
  std::string track_id_file;  // optional: last track numbers, kept across restarts
  // The LiDAR's rays (columns over one turn, rings from min to max elevation); the VLP-16's.
  SpinningLidarModel lidar = SpinningLidarModel::vlp16();
};

struct TrackerParameters {
  PipelineOptions pipeline;
  TrackerNodeOptions node;
};

// The detector nodelet's parameters (group "detection").
struct DetectorParameters {
  detection::DecodeOptions decode;
  detection::PnpOptions pnp;
  detection::InferenceOptions inference;
  bool use_depth = true;
  std::string image_transport = "raw";  // raw, compressed, compressedDepth (ros/image_input.hpp)
  std::string depth_transport = "raw";
  double depth_max_offset = 0.02;
  double depth_max_wait = 0.3;
  detection::DetectionScheduleOptions schedule{0.0, 0.0, 0.25};
  std::string model = "package://scene_graph_tracker/models/sgt_keypoints.yaml";
  std::string catalog = "package://scene_graph_tracker/config/objects.yaml";
  std::string mesh_dir;
};

const Schema<TrackerParameters>& trackerSchema();
const Schema<DetectorParameters>& detectorSchema();

// nullptr when there is no parameter of that name.
template <class Options>
const Param<Options>* find(const Schema<Options>& schema, const std::string& name);

// Sets one parameter. An int converts to a double parameter, nothing else converts. Throws
// ParameterError for an unknown name, a wrong type or a value outside [min, max].
template <class Options>
void set(const Schema<Options>& schema, Options& options, const std::string& name,
         const Value& value);

// Applies a YAML file (a path or package:// URI; a map, nested maps give '/'-separated names).
// Throws ParameterError
// ("FILE: refine/rounds: 50 is outside [1, 30]") for a key that is no parameter, a value of the
// wrong type or out of range, or a file that cannot be read.
template <class Options>
void applyYamlFile(const Schema<Options>& schema, Options& options, const std::string& path);
template <class Options>
void applyYaml(const Schema<Options>& schema, Options& options, const std::string& text,
               const std::string& origin);

// A parameter's name in dynamic_reconfigure: '/' -> '_'.
std::string reconfigureName(const std::string& name);

// A value as the generated files write it: numbers as the shortest text that reads back to the
// same double (float, for `single`), doubles with a '.' (YAML 1.1 reads 1e-06 as a string).
std::string formatNumber(double v, bool single);
template <class Options>
std::string format(const Param<Options>& p, const Value& v);
// "[min, max]" of a number; "" for bool and string.
template <class Options>
std::string range(const Param<Options>& p);

// The generated files (tools/print_parameters.cpp writes them; the test compares).
std::string trackerYaml();         // config/tracker.yaml
std::string detectorYaml();        // config/detector.yaml
std::string trackerReconfigure();  // cfg/Tracker.cfg
std::string trackerTables();       // the tracker's tables in doc/parameters.md, one per group
std::string detectorTables();      // the detector's
std::string trackerIndex();        // README between the "tracker parameters" markers
std::string detectorIndex();       // README between the "detector parameters" markers
std::string parameterReference();  // doc/parameters.md

// The text between `<!-- BEGIN GENERATED: what -->` and `<!-- END GENERATED: what -->` (lines of
// their own), and `text` with it replaced by `body`. Throw std::runtime_error without the markers.
std::string generatedSection(const std::string& text, const std::string& what);
std::string replaceGeneratedSection(const std::string& text, const std::string& what,
                                    const std::string& body);

}  // namespace sgt::params
