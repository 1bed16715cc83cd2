// SEMAP query latency: the SQL relation functions on a throw-away PostgreSQL + PostGIS server
// (started by the program, test/semap/pg_server.hpp) against the C++ engine's holds() on the same
// scene: a workbench with the five catalog objects on it and a relay inside the KLT (7 objects,
// 42 ordered pairs). Each benchmark runs 200 calls and reports the median per call (median_us)
// next to Google Benchmark's mean.
// - BM_SemapQueryRelations/all_strict, /all_relaxed: SELECT * FROM semap_relations(NULL, NULL,
// NULL, mode)
// - BM_SemapQueryRelations/subject: semap_relations('relay_1', NULL, NULL, 'strict')
// - BM_SemapObjectsOn, BM_SemapWhereWas: semap_objects_on('bench_1'), semap_where_was('relay_1', t)
// - BM_CoreRelationHolds: one holds() call (median over batches of all 336 pair x relation calls)
// - BM_CoreAllRelations: every relation between all pairs (what /all_strict answers), C++
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "pg_server.hpp"
#include "scene_graph_tracker/relations/spatial_relations.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/semap/bridge.hpp"

namespace sgt::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kCalls = 200;

Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

struct Scene {
  semap::Frame frame;
  std::vector<relations::OrientedBox> boxes;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene s;
    const ObjectCatalog catalog =
        loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml");
    auto shape = [&](const std::string& name) {
      return std::make_shared<const semap::ClassShape>(sgt::ros::classShape(catalog.get(name)));
    };
    auto bench = std::make_shared<semap::ClassShape>();
    bench->name = "bench", bench->box = Eigen::AlignedBox3d(Eigen::Vector3d(-0.8, -0.4, -0.9),
                                                            Eigen::Vector3d(0.8, 0.4, 0.0));
    s.frame.stamp = 100.0, s.frame.update_relations = true;
    s.frame.objects.push_back({"bench_1", bench, "map", pose(2.0, 1.0, 0.9, 0.1)});
    const std::vector<std::string> classes = {"multimeter", "screwdriver", "materialbox", "klt",
                                              "relay"};
    const double xs[5] = {-0.45, -0.2, 0.02, 0.3, 0.55}, yaws[5] = {0.3, -0.5, 0.1, 0.2, -0.2};
    const Eigen::Isometry3d& T_bench = s.frame.objects.front().T_world_object;
    for (std::size_t k = 0; k < classes.size(); ++k) {
      const auto c = shape(classes[k]);
      s.frame.objects.push_back({classes[k] + "_1", c, "bench_1",
                                 T_bench * pose(xs[k], 0.0, 0.002 - c->box.min().z(), yaws[k])});
    }
    const auto relay = shape("relay");  // a second relay inside the KLT
    s.frame.objects.push_back(
        {"relay_2", relay, "klt_1", s.frame.objects[4].T_world_object * pose(0.0, 0.0, 0.0, 0.5)});
    for (const auto& o : s.frame.objects)
      s.boxes.push_back(relations::orientedBox(o.shape->box, o.T_world_object));
    return s;
  }();
  return s;
}

// The server and a connection with the scene written; null (and `why`) when PostgreSQL is missing.
semap::SemapDb* database(std::string& why) {
  static std::unique_ptr<test::PgServer> pg;
  static std::unique_ptr<semap::SemapDb> db;
  static std::string missing = test::PgServer::missing();
  if (!db && missing.empty()) {
    pg = std::make_unique<test::PgServer>();
    db = std::make_unique<semap::SemapDb>(pg->settings());
    db->writeFrame(scene().frame);
  }
  why = missing;
  return db.get();
}

template <class F>
void medianOf(benchmark::State& state, F call) {
  std::vector<double> us;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    call();
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
  state.counters["median_us"] = us[us.size() / 2];
}

void BM_SemapQueryRelations(benchmark::State& state, const std::string& subject,
                            const std::string& mode) {
  std::string why;
  semap::SemapDb* db = database(why);
  if (!db) return state.SkipWithError(why.c_str());
  std::size_t n = 0;
  medianOf(state, [&] { n = db->relations(subject, "", "", mode).size(); });
  state.counters["relations"] = static_cast<double>(n);
}
BENCHMARK_CAPTURE(BM_SemapQueryRelations, all_strict, "", "strict")
    ->Iterations(kCalls)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SemapQueryRelations, all_relaxed, "", "relaxed")
    ->Iterations(kCalls)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SemapQueryRelations, subject, "relay_1", "strict")
    ->Iterations(kCalls)
    ->Unit(benchmark::kMillisecond);

void BM_SemapObjectsOn(benchmark::State& state) {
  std::string why;
  semap::SemapDb* db = database(why);
  if (!db) return state.SkipWithError(why.c_str());
  std::size_t n = 0;
  medianOf(state, [&] { n = db->objectsOn("bench_1", "strict").size(); });
  state.counters["objects"] = static_cast<double>(n);
}
BENCHMARK(BM_SemapObjectsOn)->Iterations(kCalls)->Unit(benchmark::kMillisecond);

void BM_SemapWhereWas(benchmark::State& state) {
  std::string why;
  semap::SemapDb* db = database(why);
  if (!db) return state.SkipWithError(why.c_str());
  medianOf(state, [&] { benchmark::DoNotOptimize(db->whereWas("relay_1", 100.5)); });
}
BENCHMARK(BM_SemapWhereWas)->Iterations(kCalls)->Unit(benchmark::kMillisecond);

// All ordered pairs x all relations with the engine; returns how many hold.
int coreAll(relations::Mode mode) {
  const auto& b = scene().boxes;
  int n = 0;
  for (std::size_t t = 0; t < b.size(); ++t)
    for (std::size_t r = 0; r < b.size(); ++r)
      for (int k = 0; k < relations::kRelationCount && t != r; ++k)
        n += relations::holds(static_cast<relations::Relation>(k), mode, b[t], b[r]);
  return n;
}

void BM_CoreRelationHolds(benchmark::State& state) {
  const double calls = static_cast<double>(scene().boxes.size() * (scene().boxes.size() - 1) *
                                           relations::kRelationCount);
  medianOf(state, [&] { benchmark::DoNotOptimize(coreAll(relations::Mode::Strict)); });
  state.counters["median_us"] /= calls;  // per holds() call
}
BENCHMARK(BM_CoreRelationHolds)->Iterations(kCalls)->Unit(benchmark::kMicrosecond);

void BM_CoreAllRelations(benchmark::State& state) {
  int n = 0;
  medianOf(state, [&] { n = coreAll(relations::Mode::Strict); });
  state.counters["relations"] = n;
}
BENCHMARK(BM_CoreAllRelations)->Iterations(kCalls)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace sgt::bench

BENCHMARK_MAIN();
