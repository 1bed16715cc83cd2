// Localization and pre-segmentation on the paper's frame (the ~411,698-triangle building, the
// five objects on the workbench, a 640x480 depth camera and a 1824x16 VLP-16 on the robot).
// - BM_LocalizeScan: one VLP-16 scan (1 cm range noise), robot prior 30 cm / 5 deg off; counters
//   err_mm / err_deg of the result and rays cast.
// - BM_Presegment: both sensors of the frame with things the tracker does not know in view (a
//   person beside the bench, a box on the bench, two boxes on the floor); counters: reduction of
//   the VLP-16 scan (share of its valid points that are explained, the paper's 86 %), and
//   precision / recall of the unknown label over both sensors against the simulation's owners,
//   rays cast over both sensors. BM_PresegmentCastEveryRay: the same without the depth image's
//   ranges from the map's planes (PresegmentOptions::map_planes).
#include <benchmark/benchmark.h>

#include "paper_scene.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/registration/localizer.hpp"
#include "scene_graph_tracker/segmentation/presegmentation.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::bench {
namespace {

Eigen::Isometry3d offset(double x, double y, double yaw_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  T.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

void BM_LocalizeScan(benchmark::State& state) {
  static PaperScene s = makePaperScene();
  auto rays = std::make_shared<SensorRays>(s.lidar_rays);
  const Eigen::Isometry3d T_base_lidar = s.T_world_base.inverse() * s.T_world_lidar;
  const Eigen::Isometry3d prior =
      s.T_world_base * offset(0.3 * std::cos(0.7), 0.3 * std::sin(0.7), 5.0);
  RangeMeasurements scan =
      fromRanges(SpinningLidarModel::vlp16(), rays,
                 simulate(*s.scene, *rays, s.T_world_lidar).range, prior * T_base_lidar);
  addRangeNoise(scan, 0.01, 4);
  const Localizer localizer;
  LocalizeResult r;
  for (auto _ : state) r = localizer.localize(*s.scene, {scan}, prior);
  state.counters["err_mm"] =
      (r.T_map_base.translation() - s.T_world_base.translation()).norm() * 1000.0;
  state.counters["err_deg"] =
      Eigen::AngleAxisd(r.T_map_base.linear() * s.T_world_base.linear().transpose()).angle() *
      180.0 / M_PI;
  state.counters["rays_cast"] = static_cast<double>(r.rays_cast);
  state.counters["ok"] = r.status == LocalizeStatus::kOk;
}
BENCHMARK(BM_LocalizeScan)->Unit(benchmark::kMillisecond)->UseRealTime();

void presegmentFrame(benchmark::State& state, bool map_planes) {
  static PaperScene s = makePaperScene();
  const Eigen::Vector3d top = s.building.workbench_top_centre.cast<double>();
  std::vector<NodeId> unknown;
  const auto add = [&](const TriangleMesh& mesh, const Eigen::Vector3d& p) {
    const NodeId node = 900 + static_cast<NodeId>(unknown.size());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = p;
    s.scene->addInstance(node, s.scene->addMesh(std::make_shared<TriangleMesh>(mesh)), T);
    unknown.push_back(node);
  };
  add(makeCylinder(0.25f, 1.75f, 48), {top.x() + 1.1, top.y() + 0.3, 0.875});  // a person
  add(makeBox({0.12f, 0.1f, 0.15f}),
      top + Eigen::Vector3d(-0.05, -0.2, 0.075));                            // a box on the bench
  add(makeBox({0.5f, 0.4f, 0.45f}), {top.x() - 1.3, top.y() + 1.5, 0.225});  // boxes on the floor
  add(makeBox({0.4f, 0.4f, 0.8f}), {top.x() + 0.9, top.y() + 2.6, 0.4});
  s.scene->commit();
  auto cam_rays = std::make_shared<SensorRays>(s.camera_rays);
  auto lidar_rays = std::make_shared<SensorRays>(s.lidar_rays);
  const SimulatedScan cam = simulate(*s.scene, *cam_rays, s.T_world_camera);
  const SimulatedScan lidar = simulate(*s.scene, *lidar_rays, s.T_world_lidar);
  std::vector<RangeMeasurements> frame;
  frame.push_back(fromDepthImage(s.camera, cam_rays, depthImage(cam, *cam_rays), s.T_world_camera));
  addDepthNoise(frame.back(), 0.0015, 1);
  frame.push_back(
      fromRanges(SpinningLidarModel::vlp16(), lidar_rays, lidar.range, s.T_world_lidar));
  addRangeNoise(frame.back(), 0.01, 2);
  for (const NodeId n : unknown)
    s.scene->setInstanceEnabled(n, false);  // the tracker does not know them
  s.scene->commit();

  std::vector<Presegmentation> result(2);
  PresegmentOptions options;
  options.map_planes = map_planes;
  for (auto _ : state)
    for (std::size_t k = 0; k < frame.size(); ++k)
      result[k] = presegment(*s.scene, frame[k], options);

  std::size_t tp = 0, fp = 0, fn = 0;
  const SimulatedScan* truth[2] = {&cam, &lidar};
  for (std::size_t k = 0; k < frame.size(); ++k)
    for (std::size_t i = 0; i < frame[k].size(); ++i) {
      if (!frame[k].valid(i)) continue;
      const bool is = std::find(unknown.begin(), unknown.end(), truth[k]->node[i]) != unknown.end();
      const bool said = result[k].label[i] == PointLabel::kUnknown;
      tp += is && said, fp += !is && said, fn += is && !said;
    }
  state.counters["rays_cast"] = static_cast<double>(result[0].rays_cast + result[1].rays_cast);
  state.counters["reduction"] = result[1].counts.reduction();
  state.counters["lidar_valid"] = static_cast<double>(result[1].counts.valid());
  state.counters["lidar_unknown"] = static_cast<double>(result[1].counts.unknown);
  state.counters["precision"] = tp + fp ? static_cast<double>(tp) / (tp + fp) : 0.0;
  state.counters["recall"] = tp + fn ? static_cast<double>(tp) / (tp + fn) : 0.0;
  state.SetLabel(meshLabel(s));
  for (const NodeId n : unknown) s.scene->removeInstance(n);
  s.scene->commit();
}
void BM_Presegment(benchmark::State& state) { presegmentFrame(state, true); }
void BM_PresegmentCastEveryRay(benchmark::State& state) { presegmentFrame(state, false); }
BENCHMARK(BM_Presegment)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PresegmentCastEveryRay)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace sgt::bench

BENCHMARK_MAIN();
