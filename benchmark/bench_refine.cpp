// Object refinement on the paper's frame: 640x480 depth + 1824x16 VLP-16 of the five paper
// objects on the workbench in the generated building, initial errors 3 cm / 10 deg, depth noise
// 1.5 mm at 1 m (z^2), LiDAR noise 1 cm. Argument: occlusion in percent — a board that is not in
// the tracker's scene stands between the camera and the objects, hiding that share of the
// objects' camera pixels. Counter add_s_mm: mean ADD-S over the five objects after refinement.
// The refiner runs with the options the tracker gives it (PipelineOptions::refiner), or with
// those of the parameter file in BENCH_PARAMS (config/tracker.yaml's schema, as evaluate --params).
// BM_PclIcpFrame / BM_PclIcpPointToPointFrame: the PCL ICP baseline on the same frames (see
// pcl_icp_baseline.hpp), point-to-plane and point-to-point.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <random>

#include "paper_scene.hpp"
#ifdef SGT_HAVE_PCL
#include "pcl_icp_baseline.hpp"
#endif
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/pipeline/pipeline_options.hpp"
#include "scene_graph_tracker/registration/object_refiner.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::bench {
namespace {

// The tracker's refiner options, with BENCH_PARAMS's file applied when it is set.
RefinerOptions refinerOptions() {
  params::TrackerParameters p;
  if (const char* path = std::getenv("BENCH_PARAMS"); path && *path)
    params::applyYamlFile(params::trackerSchema(), p, path);
  return p.pipeline.refiner;
}

struct Frame {
  PaperScene s = makePaperScene();
  std::vector<RangeMeasurements> measurements;
  std::vector<Eigen::Isometry3d> initial;
  std::vector<std::vector<Eigen::Vector3f>> samples;  // per object, 1000 surface points
};

// Camera pixels that show one of the five objects.
std::size_t objectPixels(const PaperScene& s, const SensorRays& rays) {
  const SimulatedScan scan = simulate(*s.scene, rays, s.T_world_camera);
  std::size_t n = 0;
  for (const NodeId node : scan.node)
    for (const auto& o : s.objects) n += node == o.node;
  return n;
}

// A wide board 0.3 m in front of the objects (towards the robot) whose top edge is raised until
// it hides `fraction` of the objects' camera pixels (bisection); the LiDAR, lower down, loses
// more. It is in the simulated world only, not in the tracker's scene.
void placeOccluder(PaperScene& s, NodeId board, const SensorRays& camera_rays, double fraction) {
  const Eigen::Vector3d top = s.building.workbench_top_centre.cast<double>();
  TriangleMesh b = makeBox({1.6f, 0.01f, 1.0f});
  b.transform(Eigen::Isometry3f(Eigen::Translation3f(0, 0, -0.5f)));  // origin at the top edge
  const double all = static_cast<double>(objectPixels(s, camera_rays));
  s.scene->addInstance(board, s.scene->addMesh(std::make_shared<TriangleMesh>(b)),
                       Eigen::Isometry3d::Identity());
  double lo = -0.3, hi = 0.4;  // top edge relative to the bench top
  for (int i = 0; i < 14; ++i) {
    const double mid = 0.5 * (lo + hi);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = top + Eigen::Vector3d(0, 0.3, mid);
    s.scene->setInstancePose(board, T);
    s.scene->commit();
    const double hidden = 1.0 - objectPixels(s, camera_rays) / all;
    (hidden < fraction ? lo : hi) = mid;
  }
}

Frame makeFrame(int occlusion_percent) {
  Frame f;
  PaperScene& s = f.s;
  auto camera_rays = std::make_shared<SensorRays>(s.camera_rays);
  auto lidar_rays = std::make_shared<SensorRays>(s.lidar_rays);
  const NodeId board = 999;
  if (occlusion_percent > 0) placeOccluder(s, board, *camera_rays, occlusion_percent / 100.0);
  const SimulatedScan cam = simulate(*s.scene, *camera_rays, s.T_world_camera);
  f.measurements.push_back(
      fromDepthImage(s.camera, camera_rays, depthImage(cam, *camera_rays), s.T_world_camera));
  addDepthNoise(f.measurements.back(), 0.0015, 1);
  const SimulatedScan lidar = simulate(*s.scene, *lidar_rays, s.T_world_lidar);
  f.measurements.push_back(
      fromRanges(SpinningLidarModel::vlp16(), lidar_rays, lidar.range, s.T_world_lidar));
  addRangeNoise(f.measurements.back(), 0.01, 2);
  if (s.scene->hasInstance(board)) s.scene->removeInstance(board);
  s.scene->commit();
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (const auto& o : s.objects) {
    Eigen::Isometry3d T = o.T_world_object;
    T.translation() += Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized() * 0.03;
    T.linear() =
        Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized())
            .toRotationMatrix() *
        T.linear();
    f.initial.push_back(T);
    f.samples.push_back(sampleSurface(*s.object_meshes[o.mesh - 1], 1000, 5).points);
  }
  return f;
}

double addS(const std::vector<Eigen::Vector3f>& pts, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3f E = est.cast<float>(), T = truth.cast<float>();
  std::vector<Eigen::Vector3f> true_pts;
  for (const auto& p : pts) true_pts.push_back(T * p);
  double sum = 0;
  for (const auto& p : pts) {
    const Eigen::Vector3f q = E * p;
    float best = std::numeric_limits<float>::max();
    for (const auto& t : true_pts) best = std::min(best, (q - t).squaredNorm());
    sum += std::sqrt(best);
  }
  return sum / pts.size();
}

// One frame per occlusion, shared by all benchmarks.
Frame& frame(int occlusion_percent) {
  static std::map<int, Frame> frames;
  auto it = frames.find(occlusion_percent);
  if (it == frames.end())
    it = frames.emplace(occlusion_percent, makeFrame(occlusion_percent)).first;
  return it->second;
}

// Counters add_s_mm (the mean over the five objects) and add_s_mm_<class> (each object's): the
// mean alone hides which object an error comes from.
void setAddSCounters(benchmark::State& state, const Frame& f,
                     const std::vector<Eigen::Isometry3d>& estimates) {
  double add_s = 0;
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    const double mm = addS(f.samples[k], estimates[k], f.s.objects[k].T_world_object) * 1000.0;
    state.counters["add_s_mm_" + f.s.objects[k].class_name] = mm;
    add_s += mm / estimates.size();
  }
  state.counters["add_s_mm"] = add_s;
}

void BM_RefineFrame(benchmark::State& state) {
  Frame& f = frame(static_cast<int>(state.range(0)));
  std::vector<RefineTarget> targets;
  for (const auto& o : f.s.objects) targets.push_back({o.node, nullptr});
  const ObjectRefiner refiner(refinerOptions());
  RefineResult result;
  for (auto _ : state) {
    state.PauseTiming();
    for (std::size_t k = 0; k < targets.size(); ++k)
      f.s.scene->setInstancePose(targets[k].node, f.initial[k]);
    f.s.scene->commit();
    state.ResumeTiming();
    result = refiner.refine(*f.s.scene, targets, f.measurements);
  }
  std::vector<Eigen::Isometry3d> estimates;
  for (const ObjectEstimate& e : result.objects) estimates.push_back(e.T_world_object);
  setAddSCounters(state, f, estimates);
  state.counters["rays_cast"] = static_cast<double>(result.rays_cast);
  state.SetLabel(meshLabel(f.s));
}
BENCHMARK(BM_RefineFrame)->Arg(0)->Arg(30)->Arg(60)->Unit(benchmark::kMillisecond)->UseRealTime();

// Cost per object on one core: each iteration refines one object alone (the five in turn, each
// from its initial error; the others stay at theirs), with TBB limited to one thread, from the
// depth image alone: what the tracker refines objects from when a frame has one (refine_with_lidar
// off), and what a depth tracker such as ICG sees. Counters: ms_per_object (wall time per
// iteration), add_s_mm (mean ADD-S of the five objects' last refinements) and add_s_mm_<class>.
// A neighbour left at its initial error can take an object's rays (the material box's do).
void BM_RefineObjectOneCore(benchmark::State& state) {
  Frame& f = frame(0);
  tbb::global_control one_core(tbb::global_control::max_allowed_parallelism, 1);
  const ObjectRefiner refiner(refinerOptions());
  const std::vector<RangeMeasurements> depth = {f.measurements.front()};
  const std::size_t n = f.s.objects.size();
  for (std::size_t k = 0; k < n; ++k) f.s.scene->setInstancePose(f.s.objects[k].node, f.initial[k]);
  std::vector<Eigen::Isometry3d> last = f.initial;
  std::size_t k = 0;
  double total_ms = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    const NodeId node = f.s.objects[k].node;
    f.s.scene->setInstancePose(node, f.initial[k]);
    f.s.scene->commit();
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    const RefineResult r = refiner.refine(*f.s.scene, {{node, nullptr}}, depth);
    total_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    state.PauseTiming();
    last[k] = r.objects.front().T_world_object;
    f.s.scene->setInstancePose(node, f.initial[k]);  // the next objects see this one where it was
    k = (k + 1) % n;
    state.ResumeTiming();
  }
  for (std::size_t j = 0; j < n; ++j) f.s.scene->setInstancePose(f.s.objects[j].node, f.initial[j]);
  f.s.scene->commit();
  state.counters["ms_per_object"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / 1000.0,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  setAddSCounters(state, f, last);
  state.SetLabel(meshLabel(f.s));
}
BENCHMARK(BM_RefineObjectOneCore)->Unit(benchmark::kMillisecond)->UseRealTime();

#ifdef SGT_HAVE_PCL  // the PCL ICP baseline: built when CMake finds PCL
// Every valid measurement as a world point: origin + R * (direction * range).
std::vector<Eigen::Vector3f> worldPoints(const std::vector<RangeMeasurements>& measurements) {
  std::vector<Eigen::Vector3f> out;
  for (const RangeMeasurements& m : measurements) {
    const Eigen::Isometry3f T = m.T_world_sensor.cast<float>();
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (!m.valid(i)) continue;
      const Eigen::Vector3f o =
          m.rays->origins.empty() ? Eigen::Vector3f::Zero() : m.rays->origins[i];
      out.push_back(T * (o + m.pointInSensor(i)));
    }
  }
  return out;
}

// PCL ICP from the same initial poses against the same measurements. Per object: target = 3000
// surface samples (with face normals) of the model, source = the measured points in the
// object's box at the initial pose grown by the refiner's roi_margin; objects in parallel
// (tbb::parallel_for, like the refiner). Iteration budget = the refiner's rounds x steps (>= 24),
// stopping at its step tolerance. Timed: crop, clouds, kd-trees, ICP. Not timed: turning the
// ranges into world points, done once per frame (the refiner takes the ranges as they are).
// max_dist: PCL's fixed max correspondence distance, the best of 5/7/10/12/15/20/30/40/50 mm
// at 0 % occlusion for each variant (smaller keeps the workbench points out of the fit).
void pclIcpFrame(benchmark::State& state, bool point_to_plane, double max_dist) {
  const Frame& f = frame(static_cast<int>(state.range(0)));
  const RefinerOptions refiner;
  PclIcpOptions options;
  options.point_to_plane = point_to_plane;
  options.max_iterations = std::max(24, refiner.rounds * refiner.steps);
  options.max_correspondence_distance = max_dist;
  options.crop_margin = refiner.roi_margin;
  options.transformation_epsilon = refiner.step_tolerance * refiner.step_tolerance;
  std::vector<PclIcpModel> models;
  std::vector<PlainPose> initial;
  for (std::size_t k = 0; k < f.s.objects.size(); ++k) {
    const TriangleMesh& mesh = *f.s.object_meshes[f.s.objects[k].mesh - 1];
    SurfaceSample sample = sampleSurface(mesh, 3000, 11);
    const Eigen::AlignedBox3f box = mesh.boundingBox();
    models.push_back({std::move(sample.points), std::move(sample.normals), box.min(), box.max()});
    initial.push_back(f.initial[k].matrix());
  }
  const std::vector<Eigen::Vector3f> points = worldPoints(f.measurements);
  std::vector<PlainPose> result;
  for (auto _ : state) result = pclIcpRefine(models, points, initial, options);
  std::vector<Eigen::Isometry3d> estimates;
  for (const PlainPose& T : result) estimates.emplace_back(Eigen::Matrix4d(T));
  setAddSCounters(state, f, estimates);
  state.SetLabel(meshLabel(f.s));
}
void BM_PclIcpFrame(benchmark::State& state) { pclIcpFrame(state, true, 0.010); }  // point-to-plane
void BM_PclIcpPointToPointFrame(benchmark::State& state) { pclIcpFrame(state, false, 0.015); }
BENCHMARK(BM_PclIcpFrame)->Arg(0)->Arg(30)->Arg(60)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclIcpPointToPointFrame)
    ->Arg(0)
    ->Arg(30)
    ->Arg(60)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

#endif  // SGT_HAVE_PCL

}  // namespace
}  // namespace sgt::bench

BENCHMARK_MAIN();
