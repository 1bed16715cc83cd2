#include "scene_graph_tracker/scene/raycast_scene.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <tuple>

namespace sgt {
namespace {

RTCBuildQuality quality(int q) {
  return q <= 0   ? RTC_BUILD_QUALITY_LOW
         : q == 1 ? RTC_BUILD_QUALITY_MEDIUM
                  : RTC_BUILD_QUALITY_HIGH;
}

void checkDevice(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree error ") + std::to_string(err) + " in " + what);
}

// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3f closestOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                  const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
  const Eigen::Vector3f ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3f bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Eigen::Vector3f cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Per triangle: unit normal and offset (n.p + d = 0 on its plane); zero for a degenerate one,
// which then never rules its triangle out.
std::vector<TrianglePlane> trianglePlanes(const TriangleMesh& m) {
  std::vector<TrianglePlane> planes(m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    const Eigen::Vector3f a = m.vertices[t[0]];
    const Eigen::Vector3f n = (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a);
    if (!(n.norm() > 0.0f)) continue;
    planes[i].normal = n.normalized();
    planes[i].offset = -planes[i].normal.dot(a);
  }
  return planes;
}

struct PointQueryState {
  const TriangleMesh* mesh;
  const std::vector<TrianglePlane>* planes;
  Eigen::Vector3f best;
  std::uint32_t primitive;
  bool found = false;
};

bool closestTriangleCallback(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<PointQueryState*>(args->userPtr);
  const Triangle& t = state->mesh->triangles[args->primID];
  const auto& v = state->mesh->vertices;
  const Eigen::Vector3f q(args->query->x, args->query->y, args->query->z);
  // The distance to the triangle's plane never exceeds the distance to the triangle: a plane
  // beyond the radius (with a margin over float rounding) rules the triangle out cheaply, and
  // exactly where the full test below would have.
  const TrianglePlane& plane = (*state->planes)[args->primID];
  if (std::abs(plane.normal.dot(q) + plane.offset) > args->query->radius * 1.0001f + 1e-7f)
    return false;
  const Eigen::Vector3f c = closestOnTriangle(q, v[t[0]], v[t[1]], v[t[2]]);
  const float d = (c - q).norm();
  if (d >= args->query->radius) return false;
  args->query->radius = d;  // shrinks the search
  state->best = c;
  state->primitive = args->primID;
  state->found = true;
  return true;
}

}  // namespace

void RayHits::resize(int w, int h) {
  width = w;
  height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  if (range.size() == n) return;
  range.assign(n, std::numeric_limits<float>::infinity());
  point.assign(n, Eigen::Vector3f::Zero());
  normal.assign(n, Eigen::Vector3f::Zero());
  node.assign(n, kNoNode);
  primitive.assign(n, 0);
}

namespace {

struct HitsPool {
  std::mutex mutex;
  std::map<std::pair<int, int>, std::vector<std::unique_ptr<RayHits>>> free;  // by grid size
  std::size_t pooled = 0;
};

HitsPool& hitsPool() {
  static HitsPool* pool = new HitsPool;  // never destroyed: leases may end during exit
  return *pool;
}

}  // namespace

HitsLease scratchHits(int width, int height) {
  HitsPool& pool = hitsPool();
  std::unique_ptr<RayHits> hits;
  {
    std::lock_guard<std::mutex> lock(pool.mutex);
    auto& free = pool.free[{width, height}];
    if (!free.empty()) {
      hits = std::move(free.back());
      free.pop_back();
    } else {
      ++pool.pooled;
    }
  }
  if (!hits) hits = std::make_unique<RayHits>();
  hits->resize(width, height);
  return HitsLease(std::move(hits));
}

HitsLease::~HitsLease() {
  if (!hits_) return;  // moved from
  HitsPool& pool = hitsPool();
  std::lock_guard<std::mutex> lock(pool.mutex);
  pool.free[{hits_->width, hits_->height}].push_back(std::move(hits_));
}

std::size_t scratchHitsPooled() {
  std::lock_guard<std::mutex> lock(hitsPool().mutex);
  return hitsPool().pooled;
}

// ------------------------------------------------------------------------------- RaycastScene
RaycastScene::RaycastScene(const RaycastSceneOptions& options) : options_(options) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  top_ = rtcNewScene(device_);
  rtcSetSceneFlags(top_, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_LOW);
  rtcCommitScene(top_);
  checkDevice(device_, "scene creation");
}

RaycastScene::~RaycastScene() {
  rtcReleaseScene(top_);
  for (auto* s : mesh_scenes_) rtcReleaseScene(s);
  rtcReleaseDevice(device_);
}

MeshId RaycastScene::addMesh(std::shared_ptr<const TriangleMesh> mesh) {
  if (!mesh || mesh->empty()) throw std::invalid_argument("RaycastScene::addMesh: empty mesh");
  RTCScene scene = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene, quality(options_.object_build_quality));
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                        mesh->vertices.size()));
  for (std::size_t i = 0; i < mesh->vertices.size(); ++i)
    for (int c = 0; c < 3; ++c) v[3 * i + c] = mesh->vertices[i][c];
  auto* idx = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(std::uint32_t), mesh->triangles.size()));
  for (std::size_t i = 0; i < mesh->triangles.size(); ++i)
    for (int c = 0; c < 3; ++c) idx[3 * i + c] = mesh->triangles[i][c];
  rtcSetGeometryBuildQuality(geom, quality(options_.object_build_quality));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  checkDevice(device_, "mesh BVH build");
  boxes_.push_back(mesh->boundingBox());
  planes_.push_back(trianglePlanes(*mesh));
  meshes_.push_back(std::move(mesh));
  mesh_scenes_.push_back(scene);
  return static_cast<MeshId>(meshes_.size() - 1);
}

const TriangleMesh& RaycastScene::mesh(MeshId id) const {
  if (id < 0 || static_cast<std::size_t>(id) >= meshes_.size())
    throw std::out_of_range("RaycastScene: unknown mesh id " + std::to_string(id));
  return *meshes_[id];
}

const Eigen::AlignedBox3f& RaycastScene::meshBox(MeshId id) const {
  mesh(id);  // checks the id
  return boxes_[id];
}

void RaycastScene::setStaticMap(std::shared_ptr<const TriangleMesh> map, NodeId node) {
  if (static_map_node_ != kNoNode) removeInstance(static_map_node_);
  const int saved = options_.object_build_quality;
  options_.object_build_quality = options_.static_map_build_quality;
  static_map_mesh_ = addMesh(std::move(map));
  options_.object_build_quality = saved;
  static_map_node_ = node;
  attachInstance(node, static_map_mesh_, Eigen::Isometry3d::Identity());
}

unsigned RaycastScene::slotFor(NodeId node) const {
  const auto it = slot_of_node_.find(node);
  if (it == slot_of_node_.end())
    throw std::out_of_range("RaycastScene: node " + std::to_string(node) + " has no instance");
  return it->second;
}

void RaycastScene::writeTransform(unsigned slot, const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite())
    throw std::invalid_argument("RaycastScene: non-finite pose for node " +
                                std::to_string(slots_[slot].node));
  RTCGeometry geom = rtcGetGeometry(top_, slot);
  const Eigen::Matrix<float, 3, 4> m =
      T.matrix().topRows<3>().cast<float>();  // column-major storage
  rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
  rtcCommitGeometry(geom);
  slots_[slot].T = T;
  slots_[slot].R = T.linear().cast<float>();
  dirty_ = true;
}

unsigned RaycastScene::attachInstance(NodeId node, MeshId mesh_id, const Eigen::Isometry3d& T) {
  if (node == kNoNode) throw std::invalid_argument("RaycastScene: instance needs a node id");
  if (slot_of_node_.count(node))
    throw std::invalid_argument("RaycastScene: node " + std::to_string(node) +
                                " already has an instance");
  mesh(mesh_id);  // range check
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, mesh_scenes_[mesh_id]);
  rtcSetGeometryTimeStepCount(geom, 1);
  unsigned slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<unsigned>(slots_.size());
    slots_.emplace_back();
  }
  rtcAttachGeometryByID(top_, geom, slot);  // dense ids keep commits cheap
  rtcReleaseGeometry(geom);
  slots_[slot].node = node;
  slots_[slot].mesh = mesh_id;
  slot_of_node_[node] = slot;
  writeTransform(slot, T);
  checkDevice(device_, "instance creation");
  return slot;
}

void RaycastScene::addInstance(NodeId node, MeshId mesh_id, const Eigen::Isometry3d& T) {
  attachInstance(node, mesh_id, T);
}

void RaycastScene::setInstancePose(NodeId node, const Eigen::Isometry3d& T) {
  writeTransform(slotFor(node), T);
}

void RaycastScene::removeInstance(NodeId node) {
  const unsigned slot = slotFor(node);
  rtcDetachGeometry(top_, slot);
  slots_[slot] = Slot{};
  free_slots_.push_back(slot);
  slot_of_node_.erase(node);
  if (node == static_map_node_) static_map_node_ = kNoNode;
  dirty_ = true;
}

void RaycastScene::setInstanceEnabled(NodeId node, bool enabled) {
  const unsigned slot = slotFor(node);
  RTCGeometry geom = rtcGetGeometry(top_, slot);
  enabled ? rtcEnableGeometry(geom) : rtcDisableGeometry(geom);
  slots_[slot].enabled = enabled;
  dirty_ = true;
}

std::vector<NodeId> RaycastScene::enabledInstances() const {
  std::vector<NodeId> out;
  for (const Slot& s : slots_)
    if (s.node != kNoNode && s.enabled) out.push_back(s.node);
  return out;
}

Eigen::Isometry3d RaycastScene::instancePose(NodeId node) const { return slots_[slotFor(node)].T; }
MeshId RaycastScene::instanceMesh(NodeId node) const { return slots_[slotFor(node)].mesh; }

void RaycastScene::commit() {
  rtcCommitScene(top_);
  checkDevice(device_, "scene commit");
  dirty_ = false;
}

namespace {

// Fills lane k of a 16-ray packet; the hit starts out as "nothing".
void setLane(RTCRayHit16& rh, int k, const Eigen::Vector3f& org, const Eigen::Vector3f& dir,
             float tnear, float tfar) {
  rh.ray.org_x[k] = org.x(), rh.ray.org_y[k] = org.y(), rh.ray.org_z[k] = org.z();
  rh.ray.dir_x[k] = dir.x(), rh.ray.dir_y[k] = dir.y(), rh.ray.dir_z[k] = dir.z();
  rh.ray.tnear[k] = tnear;
  rh.ray.tfar[k] = tfar;
  rh.ray.time[k] = 0.0f;
  rh.ray.mask[k] = 0xFFFFFFFFu;
  rh.ray.id[k] = k;
  rh.ray.flags[k] = 0;
  rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

// Makes every lane of a packet inactive: an empty segment (tnear > tfar). The valid mask alone is
// not enough: where the CPU has no native 16-wide packets (AVX2 without AVX-512) Embree traces a
// 16-ray packet as a ray stream, which ignores the mask and takes every lane whose tnear <= tfar
// as a ray to trace. Only the segment is written: setLane fills the lanes that are used.
void clearPacket(RTCRayHit16& rh, int valid[16]) {
  for (int k = 0; k < 16; ++k) {
    valid[k] = 0;
    rh.ray.tnear[k] = 1.0f;
    rh.ray.tfar[k] = 0.0f;
  }
}

}  // namespace

void RaycastScene::cast(const SensorRays& rays, const Eigen::Isometry3d& T_world_sensor,
                        RayHits& hits, const TileSet* tiles, const CastLimit& limit,
                        unsigned attributes) const {
  if (dirty_) throw std::logic_error("RaycastScene::cast: commit() the scene after changing it");
  if (limit.range && limit.range->size() != rays.size())
    throw std::invalid_argument("RaycastScene::cast: " + std::to_string(limit.range->size()) +
                                " range limits for " + std::to_string(rays.size()) + " rays");
  hits.resize(rays.width, rays.height);
  if (rays.size() == 0) return;
  const TileSet all = tiles ? TileSet() : TileSet::all(rays);
  const TileSet& set = tiles ? *tiles : all;
  const Eigen::Matrix3f R = T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f o = T_world_sensor.translation().cast<float>();
  const bool per_ray_origin = !rays.origins.empty();
  RTCScene scene = top_;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, set.tiles().size(), 16), [&](const auto& block) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        alignas(64) int valid[16];
        RTCRayHit16 rh;
        std::size_t index[16];
        for (std::size_t b = block.begin(); b != block.end(); ++b) {
          clearPacket(rh, valid);
          set.forTile(rays, b, [&](int k, std::size_t i) {
            float far = rays.range_max;
            if (limit.range) {
              const float r = (*limit.range)[i];
              if (!std::isfinite(r)) {
                hits.range[i] = std::numeric_limits<float>::infinity();
                hits.node[i] = kNoNode;
                return;
              }
              far = std::min(far, r + limit.slack.at(r));
            }
            valid[k] = -1;
            index[k] = i;
            setLane(rh, k, per_ray_origin ? Eigen::Vector3f(o + R * rays.origins[i]) : o,
                    R * rays.directions[i], rays.range_min, far);
          });
          rtcIntersect16(valid, scene, &context, &rh);
          for (int k = 0; k < 16; ++k)
            if (valid[k]) writeHit(rh, k, index[k], hits, attributes);
        }
      });
}

void RaycastScene::cast(const std::vector<WorldRay>& rays, RayHits& hits) const {
  if (dirty_) throw std::logic_error("RaycastScene::cast: commit() the scene after changing it");
  hits.resize(static_cast<int>(rays.size()), 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (rays.size() + 15) / 16, 16),
                    [&](const auto& block) {
                      RTCIntersectContext context;
                      rtcInitIntersectContext(&context);
                      alignas(64) int valid[16];
                      RTCRayHit16 rh;
                      for (std::size_t b = block.begin(); b != block.end(); ++b) {
                        clearPacket(rh, valid);
                        for (int k = 0; k < 16; ++k) {
                          const std::size_t i = b * 16 + k;
                          if (i >= rays.size()) break;
                          valid[k] = -1;
                          setLane(rh, k, rays[i].origin, rays[i].direction, 0.0f, rays[i].far);
                        }
                        rtcIntersect16(valid, top_, &context, &rh);
                        for (int k = 0; k < 16; ++k)
                          if (valid[k]) writeHit(rh, k, b * 16 + k, hits);
                      }
                    });
}

bool RaycastScene::closestPoint(MeshId mesh, const Eigen::Vector3f& p, float radius,
                                SurfacePoint& out) const {
  const TriangleMesh& m = this->mesh(mesh);
  RTCPointQuery query;
  query.x = p.x(), query.y = p.y(), query.z = p.z();
  query.radius = radius;
  query.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  PointQueryState state{&m, &planes_[mesh], Eigen::Vector3f::Zero(), 0};
  rtcPointQuery(mesh_scenes_[mesh], &query, &context, closestTriangleCallback, &state);
  if (!state.found) return false;
  const Eigen::Vector3f& n = planes_[mesh][state.primitive].normal;  // zero: degenerate
  out.point = state.best;
  out.normal = n.isZero(0.0f) ? Eigen::Vector3f::UnitZ() : n;
  out.distance = (state.best - p).norm();
  return true;
}

void RaycastScene::writeHit(const RTCRayHit16& rh, int k, std::size_t i, RayHits& hits,
                            unsigned attributes) const {
  if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
    hits.range[i] = std::numeric_limits<float>::infinity();
    hits.node[i] = kNoNode;
    return;
  }
  const float r = rh.ray.tfar[k];
  const Slot& s = slots_[rh.hit.instID[0][k]];
  hits.range[i] = r;
  hits.node[i] = s.node;
  if (attributes == kRangeAndNodeOnly) return;
  const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
  if (attributes & kHitNormal) {
    Eigen::Vector3f n = s.R * Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]);
    n.normalize();
    if (n.dot(d) > 0.0f) n = -n;
    hits.normal[i] = n;
  }
  if (attributes & kHitPoint)
    hits.point[i] = Eigen::Vector3f(rh.ray.org_x[k], rh.ray.org_y[k], rh.ray.org_z[k]) + r * d;
  if (attributes & kHitPrimitive) hits.primitive[i] = rh.hit.primID[k];
}

}  // namespace sgt
