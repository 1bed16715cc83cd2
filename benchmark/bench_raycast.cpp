// Ray-casting throughput on the paper's frame (640x480 pinhole + 1824x16 VLP-16 = 336,384 rays)
// through the project's scene API and through the fastest raw Embree loop (the ceiling), the
// cost of moving instances, and how frame time grows with the number of instances.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <map>

#include "paper_scene.hpp"

namespace sgt::bench {
namespace {

PaperScene& paperScene() {
  static PaperScene s = makePaperScene();
  return s;
}

void setCounters(benchmark::State& state, std::size_t rays) {
  state.counters["rays"] = static_cast<double>(rays);
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_PaperFrameScene(benchmark::State& state) {
  PaperScene& s = paperScene();
  RayHits camera_hits, lidar_hits;
  for (auto _ : state) {
    s.scene->cast(s.camera_rays, s.T_world_camera, camera_hits);
    s.scene->cast(s.lidar_rays, s.T_world_lidar, lidar_hits);
    benchmark::DoNotOptimize(camera_hits.range.data());
    benchmark::DoNotOptimize(lidar_hits.range.data());
  }
  setCounters(state, s.camera_rays.size() + s.lidar_rays.size());
  std::size_t on_objects = 0;
  for (NodeId n : camera_hits.node) on_objects += n >= 10;
  state.counters["camera_rays_on_objects"] = static_cast<double>(on_objects);
  state.SetLabel(meshLabel(s));
}
BENCHMARK(BM_PaperFrameScene)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same casts asking only for what the bare loop below writes: range and node
// (kRangeAndNodeOnly, as pre-segmentation casts).
void BM_PaperFrameSceneRangeNode(benchmark::State& state) {
  PaperScene& s = paperScene();
  RayHits camera_hits, lidar_hits;
  for (auto _ : state) {
    s.scene->cast(s.camera_rays, s.T_world_camera, camera_hits, nullptr, {}, kRangeAndNodeOnly);
    s.scene->cast(s.lidar_rays, s.T_world_lidar, lidar_hits, nullptr, {}, kRangeAndNodeOnly);
    benchmark::DoNotOptimize(camera_hits.range.data());
    benchmark::DoNotOptimize(lidar_hits.range.data());
  }
  setCounters(state, s.camera_rays.size() + s.lidar_rays.size());
  state.SetLabel(meshLabel(s));
}
BENCHMARK(BM_PaperFrameSceneRangeNode)->Unit(benchmark::kMillisecond)->UseRealTime();

// The ceiling: one flat Embree scene (building and the five posed objects as plain triangle
// geometry), 4x4 tiles of rtcIntersect16 with the coherent flag over both cores, writing only
// the range and geometry id.
struct RawScene {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  RawScene() {
    const PaperScene& s = paperScene();
    add(*s.map, Eigen::Isometry3f::Identity(), RTC_BUILD_QUALITY_MEDIUM);
    for (const auto& o : s.objects)
      add(*s.object_meshes[o.mesh - 1], o.T_world_object.cast<float>(), RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scene);
  }
  ~RawScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
  void add(const TriangleMesh& m, const Eigen::Isometry3f& T, RTCBuildQuality q) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.vertices.size()));
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      Eigen::Map<Eigen::Vector3f>(v + 3 * i) = T * m.vertices[i];
    auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangles.size()));
    std::memcpy(idx, m.triangles.data(), m.triangles.size() * 12);
    rtcSetGeometryBuildQuality(g, q);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
  }
};

void rawCast(RTCScene scene, const SensorRays& rays, const Eigen::Isometry3d& T,
             std::vector<float>& range, std::vector<unsigned>& geom) {
  range.resize(rays.size());
  geom.resize(rays.size());
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f o = T.translation().cast<float>();
  const int tiles_x = (rays.width + 3) / 4, tiles_y = (rays.height + 3) / 4;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y, 16),
                    [&](const tbb::blocked_range<int>& r) {
                      RTCIntersectContext ctx;
                      rtcInitIntersectContext(&ctx);
                      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
                      alignas(64) int valid[16];
                      RTCRayHit16 rh;
                      for (int t = r.begin(); t != r.end(); ++t) {
                        const int x0 = (t % tiles_x) * 4, y0 = (t / tiles_x) * 4;
                        for (int k = 0; k < 16; ++k) {
                          const int x = x0 + (k & 3), y = y0 + (k >> 2);
                          valid[k] = (x < rays.width && y < rays.height) ? -1 : 0;
                          // An empty segment: without native 16-wide packets Embree ignores the
                          // mask (RaycastScene's clearPacket says more).
                          rh.ray.tnear[k] = 1.0f, rh.ray.tfar[k] = 0.0f;
                          if (!valid[k]) continue;
                          const Eigen::Vector3f d = R * rays.directions[y * rays.width + x];
                          rh.ray.org_x[k] = o.x(), rh.ray.org_y[k] = o.y(), rh.ray.org_z[k] = o.z();
                          rh.ray.dir_x[k] = d.x(), rh.ray.dir_y[k] = d.y(), rh.ray.dir_z[k] = d.z();
                          rh.ray.tnear[k] = rays.range_min, rh.ray.tfar[k] = rays.range_max;
                          rh.ray.time[k] = 0, rh.ray.mask[k] = ~0u, rh.ray.flags[k] = 0;
                          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                        }
                        rtcIntersect16(valid, scene, &ctx, &rh);
                        for (int k = 0; k < 16; ++k) {
                          if (!valid[k]) continue;
                          const std::size_t i = (y0 + (k >> 2)) * rays.width + x0 + (k & 3);
                          range[i] = rh.ray.tfar[k];
                          geom[i] = rh.hit.geomID[k];
                        }
                      }
                    });
}

void BM_PaperFrameRaw(benchmark::State& state) {
  PaperScene& s = paperScene();
  static RawScene raw;
  std::vector<float> r1, r2;
  std::vector<unsigned> g1, g2;
  for (auto _ : state) {
    rawCast(raw.scene, s.camera_rays, s.T_world_camera, r1, g1);
    rawCast(raw.scene, s.lidar_rays, s.T_world_lidar, r2, g2);
    benchmark::DoNotOptimize(r1.data());
    benchmark::DoNotOptimize(r2.data());
  }
  setCounters(state, s.camera_rays.size() + s.lidar_rays.size());
  state.SetLabel(meshLabel(s));
}
BENCHMARK(BM_PaperFrameRaw)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_InstanceUpdate(benchmark::State& state) {
  PaperScene& s = paperScene();
  int k = 0;
  for (auto _ : state) {
    const double shift = (++k % 2) ? 0.001 : -0.001;
    for (const auto& o : s.objects) {
      Eigen::Isometry3d T = o.T_world_object;
      T.translation().x() += shift;
      s.scene->setInstancePose(o.node, T);
    }
    s.scene->commit();
  }
  for (const auto& o : s.objects) s.scene->setInstancePose(o.node, o.T_world_object);
  s.scene->commit();
  state.counters["instances_moved"] = 5;
  state.counters["scene_triangles"] = static_cast<double>(s.map->triangleCount());
}
BENCHMARK(BM_InstanceUpdate)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_InstanceScaling(benchmark::State& state) {
  static std::map<int, PaperScene> scenes;
  const int n = static_cast<int>(state.range(0));
  if (!scenes.count(n)) scenes.emplace(n, makePaperScene(n - 5));
  PaperScene& s = scenes.at(n);
  RayHits camera_hits, lidar_hits;
  for (auto _ : state) {
    s.scene->cast(s.camera_rays, s.T_world_camera, camera_hits);
    s.scene->cast(s.lidar_rays, s.T_world_lidar, lidar_hits);
    benchmark::DoNotOptimize(camera_hits.range.data());
  }
  std::size_t on_objects = 0;
  for (NodeId n_hit : camera_hits.node) on_objects += n_hit >= 10;
  state.counters["instances"] = static_cast<double>(s.scene->instanceCount() - 1);
  state.counters["camera_rays_on_objects"] = static_cast<double>(on_objects);
  setCounters(state, s.camera_rays.size() + s.lidar_rays.size());
}
BENCHMARK(BM_InstanceScaling)
    ->Arg(10)
    ->Arg(100)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace sgt::bench

BENCHMARK_MAIN();
