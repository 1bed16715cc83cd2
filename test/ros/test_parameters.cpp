// The tracker's dynamic_reconfigure type (generated from cfg/Tracker.cfg) against the parameter
// schema: every run-time parameter under its name with '_' for '/', with the schema's type,
// default and range, nothing else; values go through it unchanged. No roscore needed.
#include <gtest/gtest.h>
#include <scene_graph_tracker/TrackerConfig.h>

#include <set>

#include "scene_graph_tracker/ros/parameters.hpp"

namespace sgt::ros {
namespace {

using scene_graph_tracker::TrackerConfig;

dynamic_reconfigure::Config message(const TrackerConfig& c) {
  dynamic_reconfigure::Config m;
  c.__toMessage__(m);
  return m;
}

// A value of the message by name, as the schema holds it.
std::optional<params::Value> valueOf(const dynamic_reconfigure::Config& m,
                                     const std::string& name) {
  for (const auto& b : m.bools)
    if (b.name == name) return params::Value(static_cast<bool>(b.value));
  for (const auto& i : m.ints)
    if (i.name == name) return params::Value(static_cast<int>(i.value));
  for (const auto& d : m.doubles)
    if (d.name == name) return params::Value(d.value);
  return std::nullopt;
}

TEST(TrackerReconfigure, HoldsTheRuntimeParametersOfTheSchema) {
  const params::TrackerParameters defaults;
  const auto dflt = message(TrackerConfig::__getDefault__()),
             min = message(TrackerConfig::__getMin__()), max = message(TrackerConfig::__getMax__());
  std::set<std::string> expected;
  for (const auto& p : params::trackerSchema()) {
    if (!p.runtime) continue;
    const std::string name = params::reconfigureName(p.name);
    SCOPED_TRACE(name);
    expected.insert(name);
    const auto v = valueOf(dflt, name);
    ASSERT_TRUE(v) << "not in cfg/Tracker.cfg";
    ASSERT_EQ(v->index(), p.get(defaults).index()) << "type";
    if (p.single) {
      EXPECT_EQ(static_cast<float>(std::get<double>(*v)),
                static_cast<float>(std::get<double>(p.get(defaults))));
    } else {
      EXPECT_TRUE(*v == p.get(defaults)) << "default";
    }
    if (p.type == params::Type::kInt) {
      EXPECT_EQ(std::get<int>(*valueOf(min, name)), p.min);
      EXPECT_EQ(std::get<int>(*valueOf(max, name)), p.max);
    } else if (p.type == params::Type::kDouble) {
      EXPECT_EQ(std::get<double>(*valueOf(min, name)), p.min);
      EXPECT_EQ(std::get<double>(*valueOf(max, name)), p.max);
    }
  }
  std::set<std::string> actual;
  for (const auto& d : TrackerConfig::__getParamDescriptions__()) actual.insert(d->name);
  EXPECT_EQ(actual, expected);
}

TEST(TrackerReconfigure, ValuesPassUnchanged) {
  // Non-default values (floats among them) into a Config and back.
  params::TrackerParameters p;
  p.pipeline.refiner.rounds = 5, p.pipeline.refiner.max_dist_last = 0.0173f,
  p.pipeline.association_distance = 0.123;
  p.pipeline.localize = false,
  p.pipeline.relation_options.directional_mode = relations::Mode::Relaxed;
  TrackerConfig c = TrackerConfig::__getDefault__();
  dynamic_reconfigure::Config m = message(c);
  toReconfigure(params::trackerSchema(), p, m);
  ASSERT_TRUE(c.__fromMessage__(m));
  EXPECT_EQ(c.refine_rounds, 5);
  EXPECT_FALSE(c.localize);
  EXPECT_TRUE(c.relations_relaxed);
  params::TrackerParameters back;
  fromReconfigure(params::trackerSchema(), message(c), back);
  for (const auto& q : params::trackerSchema()) {
    if (q.runtime) {
      EXPECT_TRUE(q.get(back) == q.get(p)) << q.name;
    }
  }
  EXPECT_EQ(back.pipeline.refiner.max_dist_last, 0.0173f);
  EXPECT_EQ(back.pipeline.relation_options.directional_mode, relations::Mode::Relaxed);
}

}  // namespace
}  // namespace sgt::ros
