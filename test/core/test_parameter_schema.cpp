// The parameter schema (pipeline/parameter_schema.hpp): the committed config/*.yaml,
// cfg/Tracker.cfg and README tables are what it generates, the YAML files give exactly the option
// structs' defaults (what keeps `evaluate` bit-identical), and every entry sets a field of its own.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "scene_graph_tracker/pipeline/parameter_schema.hpp"

namespace sgt::params {
namespace {

std::string source(const std::string& relative) {
  const std::string path = std::string(SGT_SOURCE_DIR) + "/" + relative;
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* const kRegenerate =
    "differs from what the parameter schema generates: run `make params`";

TEST(ParameterSchema, CommittedFilesAreGenerated) {
  EXPECT_EQ(source("config/tracker.yaml"), trackerYaml()) << "config/tracker.yaml " << kRegenerate;
  EXPECT_EQ(source("config/detector.yaml"), detectorYaml())
      << "config/detector.yaml " << kRegenerate;
  EXPECT_EQ(source("cfg/Tracker.cfg"), trackerReconfigure()) << "cfg/Tracker.cfg " << kRegenerate;
  const std::string readme = source("README.md");
  EXPECT_EQ(generatedSection(readme, "tracker parameters"), trackerIndex())
      << "README.md " << kRegenerate;
  EXPECT_EQ(generatedSection(readme, "detector parameters"), detectorIndex())
      << "README.md " << kRegenerate;
  EXPECT_EQ(source("doc/parameters.md"), parameterReference())
      << "doc/parameters.md " << kRegenerate;
}

static_assert(std::is_trivially_copyable_v<PipelineOptions>,
              "PipelineOptions compared byte by byte");

template <class O>
void expectSameValues(const Schema<O>& schema, const O& a, const O& b, const std::string& what) {
  for (const Param<O>& p : schema)
    EXPECT_TRUE(p.get(a) == p.get(b)) << what << ": " << p.name << " is " << format(p, p.get(a))
                                      << ", default " << format(p, p.get(b));
}

TEST(ParameterSchema, TrackerYamlGivesTheStructDefaults) {
  const TrackerParameters defaults;
  TrackerParameters applied;
  unsigned char before[sizeof(PipelineOptions)];
  std::memcpy(before, &applied.pipeline, sizeof before);
  applyYamlFile(trackerSchema(), applied, std::string(SGT_SOURCE_DIR) + "/config/tracker.yaml");
  expectSameValues(trackerSchema(), applied, defaults, "config/tracker.yaml");
  // No byte of the options changes: every field, also those the schema does not name, and the
  // floats exactly (the setters assign single fields, so padding stays as it was).
  EXPECT_EQ(std::memcmp(before, &applied.pipeline, sizeof before), 0)
      << "config/tracker.yaml changes PipelineOptions";
  const TrackerNodeOptions& n = applied.node;
  const TrackerNodeOptions d;
  EXPECT_EQ(n.map_frame, d.map_frame);
  EXPECT_EQ(n.odom_frame, d.odom_frame);
  EXPECT_EQ(n.base_frame, d.base_frame);
  EXPECT_EQ(n.publish_map_odom, d.publish_map_odom);
  EXPECT_EQ(n.publish_object_tf, d.publish_object_tf);
  EXPECT_EQ(n.hypothesis_max_age, d.hypothesis_max_age);
  EXPECT_EQ(n.static_map, d.static_map);
  EXPECT_EQ(n.catalog, d.catalog);
  EXPECT_EQ(n.mesh_dir, d.mesh_dir);
}

TEST(ParameterSchema, DetectorYamlGivesTheStructDefaults) {
  const DetectorParameters d;
  DetectorParameters a;
  applyYamlFile(detectorSchema(), a, std::string(SGT_SOURCE_DIR) + "/config/detector.yaml");
  expectSameValues(detectorSchema(), a, d, "config/detector.yaml");
  EXPECT_EQ(a.decode.score_threshold, d.decode.score_threshold);
  EXPECT_EQ(a.decode.nms_iou, d.decode.nms_iou);
  EXPECT_EQ(a.decode.max_detections, d.decode.max_detections);
  EXPECT_EQ(a.pnp.min_visibility, d.pnp.min_visibility);
  EXPECT_EQ(a.pnp.max_reprojection_px, d.pnp.max_reprojection_px);
  EXPECT_EQ(a.pnp.min_depth, d.pnp.min_depth);
  EXPECT_EQ(a.use_depth, d.use_depth);
  EXPECT_EQ(a.depth_max_offset, d.depth_max_offset);
  EXPECT_EQ(a.depth_max_wait, d.depth_max_wait);
  EXPECT_EQ(a.model, d.model);
  EXPECT_EQ(a.catalog, d.catalog);
  EXPECT_EQ(a.mesh_dir, d.mesh_dir);
}

template <class O>
void expectWellFormed(const Schema<O>& schema) {
  std::set<std::string> group_names;
  for (const Group& g : groups()) group_names.insert(g.name);
  std::map<std::string, std::string> by_reconfigure_name;
  std::set<std::string> names;
  const O defaults{};
  for (const Param<O>& p : schema) {
    SCOPED_TRACE(p.name);
    EXPECT_TRUE(names.insert(p.name).second) << "declared twice";
    EXPECT_TRUE(std::regex_match(p.name, std::regex("[a-z][a-z0-9_]*(/[a-z][a-z0-9_]*)?")))
        << "name";
    EXPECT_TRUE(group_names.count(p.group)) << "group " << p.group;
    EXPECT_FALSE(p.doc.empty());
    EXPECT_EQ(p.doc.find_first_of("'\"|\n"), std::string::npos) << "doc: no quotes, | or newlines";
    EXPECT_TRUE(p.get && p.set);
    const Value v = p.get(defaults);
    EXPECT_EQ(static_cast<Type>(v.index()), p.type);
    if (p.type == Type::kInt || p.type == Type::kDouble) {
      const double x = p.type == Type::kInt ? std::get<int>(v) : std::get<double>(v);
      EXPECT_LE(p.min, x) << "default below the range";
      EXPECT_LE(x, p.max) << "default above the range";
      EXPECT_LT(p.min, p.max);
    } else {
      EXPECT_EQ(p.min, 0.0);
      EXPECT_EQ(p.max, 0.0);
      EXPECT_TRUE(p.unit.empty());
    }
    if (p.type == Type::kString) {
      EXPECT_FALSE(p.runtime) << "dynamic_reconfigure takes no strings here";
    }
    if (!p.in_file) {
      EXPECT_EQ(p.type, Type::kString) << "only paths stay out of the files";
    }
    // A dynamic_reconfigure name is no other parameter's name.
    for (const std::string& n : {p.name, reconfigureName(p.name)}) {
      const auto [it, fresh] = by_reconfigure_name.emplace(n, p.name);
      EXPECT_TRUE(fresh || it->second == p.name) << n << " is also " << it->second;
    }
  }
}

TEST(ParameterSchema, EntriesAreWellFormed) {
  expectWellFormed(trackerSchema());
  expectWellFormed(detectorSchema());
  // The groups of issue 21 are all used (and "node", "filter" besides).
  std::set<std::string> used;
  for (const auto& p : trackerSchema()) used.insert(p.group);
  for (const auto& p : detectorSchema()) used.insert(p.group);
  for (const char* g : {"association", "confirmation", "removal", "refinement", "localization",
                        "pre-segmentation", "relations", "detection", "node", "filter"})
    EXPECT_TRUE(used.count(g)) << g;
  EXPECT_EQ(used.size(), groups().size());
}

// Another value than `v` within the parameter's range.
template <class O>
Value otherValue(const Param<O>& p, const Value& v) {
  switch (p.type) {
    case Type::kBool:
      return !std::get<bool>(v);
    case Type::kInt: {
      const int i = std::get<int>(v);
      return i + 1 <= p.max ? i + 1 : i - 1;
    }
    case Type::kDouble: {
      const double d = std::get<double>(v);
      return d < p.max ? (d + p.max) / 2 : (d + p.min) / 2;
    }
    case Type::kString:
      return std::get<std::string>(v) + "x";
  }
  return v;
}

// Setting one parameter changes that one only: no two entries share a field, and each reads
// back what it sets.
template <class O>
void expectOwnFields(const Schema<O>& schema) {
  const O defaults{};
  for (const Param<O>& p : schema) {
    SCOPED_TRACE(p.name);
    O o{};
    const Value other = otherValue(p, p.get(defaults));
    set(schema, o, p.name, other);
    const Value back = p.get(o);
    if (p.single) {
      EXPECT_EQ(static_cast<float>(std::get<double>(back)),
                static_cast<float>(std::get<double>(other)));
    } else {
      EXPECT_TRUE(back == other);
    }
    EXPECT_FALSE(back == p.get(defaults));
    for (const Param<O>& q : schema) {
      if (&q != &p) {
        EXPECT_TRUE(q.get(o) == q.get(defaults)) << "setting " << p.name << " changed " << q.name;
      }
    }
  }
}

TEST(ParameterSchema, EachParameterSetsAFieldOfItsOwn) {
  expectOwnFields(trackerSchema());
  expectOwnFields(detectorSchema());
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

TEST(ParameterSchema, SetChecksNameTypeAndRange) {
  TrackerParameters t;
  EXPECT_EQ(errorOf([&] { set(trackerSchema(), t, "refine/rounds", 50); }),
            "refine/rounds: 50 is outside [1, 30]");
  EXPECT_EQ(errorOf([&] { set(trackerSchema(), t, "refine/rounds", 4.0); }),
            "refine/rounds: 4.0 is not an int");
  EXPECT_EQ(errorOf([&] { set(trackerSchema(), t, "refine/roundz", 4); }),
            "refine/roundz: no such parameter");
  EXPECT_EQ(errorOf([&] { set(trackerSchema(), t, "association_distance", 3.5); }),
            "association_distance: 3.5 is outside [0.01, 2.0]");
  set(trackerSchema(), t, "association_distance", 1);  // an int is a double too
  EXPECT_EQ(t.pipeline.association_distance, 1.0);
  set(trackerSchema(), t, "map_frame", std::string("world"));
  EXPECT_EQ(t.node.map_frame, "world");
}

TEST(ParameterSchema, YamlNestsAndRejectsUnknownKeys) {
  TrackerParameters t;
  applyYaml(trackerSchema(), t,
            "refine: {rounds: 4, max_dist_last: 0.02}\nrelations:\n  relaxed: true\nremove_after: "
            "2\nlocalize: false\n",
            "test");
  EXPECT_EQ(t.pipeline.refiner.rounds, 4);
  EXPECT_EQ(t.pipeline.refiner.max_dist_last, 0.02f);
  EXPECT_EQ(t.pipeline.relation_options.directional_mode, relations::Mode::Relaxed);
  EXPECT_EQ(t.pipeline.remove_after_s, 2.0);
  EXPECT_FALSE(t.pipeline.localize);
  EXPECT_EQ(errorOf([&] { applyYaml(trackerSchema(), t, "refine: {roundz: 4}", "f.yaml"); }),
            "f.yaml: refine/roundz: no such parameter");
  EXPECT_EQ(errorOf([&] { applyYaml(trackerSchema(), t, "refine: 4", "f.yaml"); }),
            "f.yaml: refine: no such parameter");
  EXPECT_EQ(errorOf([&] { applyYaml(trackerSchema(), t, "localize: maybe", "f.yaml"); }),
            "f.yaml: localize: 'maybe' is not a bool");
  EXPECT_EQ(errorOf([&] { applyYaml(trackerSchema(), t, "refine: {rounds: 0}", "f.yaml"); }),
            "f.yaml: refine/rounds: 0 is outside [1, 30]");
  EXPECT_EQ(errorOf([&] { applyYaml(trackerSchema(), t, "[1, 2]", "f.yaml"); }),
            "f.yaml: not a map of parameters");
  EXPECT_EQ(errorOf([&] { applyYamlFile(trackerSchema(), t, "/nonexistent.yaml"); }),
            "/nonexistent.yaml: cannot read the parameter file");
  DetectorParameters d;
  EXPECT_EQ(errorOf([&] { applyYaml(detectorSchema(), d, "refine: {rounds: 4}", "f.yaml"); }),
            "f.yaml: refine/rounds: no such parameter");
}

TEST(ParameterSchema, NumbersReadBackExactly) {
  EXPECT_EQ(formatNumber(0.06, false), "0.06");
  EXPECT_EQ(formatNumber(0.06f, true), "0.06");
  EXPECT_EQ(formatNumber(1.0, false), "1.0");
  EXPECT_EQ(formatNumber(1e-6, false), "1.0e-06");  // YAML 1.1 reads 1e-06 as a string
  EXPECT_EQ(formatNumber(5e-4, false), "5.0e-04");
  EXPECT_EQ(formatNumber(0.0015, false), "0.0015");
  EXPECT_EQ(reconfigureName("refine/max_dist_first"), "refine_max_dist_first");
}

TEST(ParameterSchema, GeneratedSections) {
  const std::string text = "a\n<!-- BEGIN GENERATED: x -->\nold\n<!-- END GENERATED: x -->\nb\n";
  EXPECT_EQ(generatedSection(text, "x"), "old\n");
  EXPECT_EQ(replaceGeneratedSection(text, "x", "new\n"),
            "a\n<!-- BEGIN GENERATED: x -->\nnew\n<!-- END GENERATED: x -->\nb\n");
  EXPECT_THROW(generatedSection(text, "y"), std::runtime_error);
}

}  // namespace
}  // namespace sgt::params
