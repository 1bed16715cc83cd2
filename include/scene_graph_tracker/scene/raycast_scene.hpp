// The ray-casting scene: the static map plus object instances on Embree 3.
//
// Every distinct mesh becomes one Embree scene (a bottom-level BVH) shared by all instances of
// it; the static map is one such mesh, instanced once with the identity. The top-level scene
// holds only instances (RTC_SCENE_FLAG_DYNAMIC, low build quality), so moving k instances and
// committing rebuilds a tree over instances, never the building's triangles.
//
// Casting goes over coherent 4x4 tiles of a sensor's ray grid with rtcIntersect16 and the
// coherent context flag, in parallel over tiles (TBB). Each ray yields its range, world hit
// point, unit world normal (instance rotation applied; faces the ray), the hit's scene-graph
// node id and primitive id.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"
#include "scene_graph_tracker/scene/node_id.hpp"
#include "scene_graph_tracker/scene/tile_set.hpp"
#include "scene_graph_tracker/sensors/range_noise.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

struct RTCDeviceTy;
struct RTCSceneTy;
struct RTCRayHit16;

namespace sgt {

using MeshId = std::int32_t;

struct RayHits {
  int width = 0;
  int height = 0;
  std::vector<float> range;              // along the unit ray; +inf when nothing was hit
  std::vector<Eigen::Vector3f> point;    // world frame
  std::vector<Eigen::Vector3f> normal;   // world frame, unit, facing the ray origin
  std::vector<NodeId> node;              // kNoNode when nothing was hit
  std::vector<std::uint32_t> primitive;  // triangle index in the hit mesh

  std::size_t size() const { return range.size(); }
  bool hit(std::size_t i) const { return node[i] != kNoNode; }
  void resize(int w, int h);
};

// RayHits fields a cast may skip (RaycastScene::cast); range and node are always written.
enum HitAttribute : unsigned {
  kHitPoint = 1u,
  kHitNormal = 2u,
  kHitPrimitive = 4u,
  kRangeAndNodeOnly = 0u,
  kAllHitAttributes = kHitPoint | kHitNormal | kHitPrimitive,
};

// Ray-hit buffers that every frame's casts reuse: a fresh 640 x 480 RayHits is 11 MB to
// allocate, fill and fault in, a cost that grew with the image rather than with the rays cast.
// scratchHits() lends a buffer of the grid's size from a process-wide pool until the lease ends;
// the pool holds as many per size as were ever leased at once. Not one per thread: a nodelet
// manager runs a node's frames on any of its many worker threads, and per-thread buffers would
// multiply by their number. A buffer keeps the hits of whatever cast used it last; rays a cast does
// not cover keep older values, so read only the tiles cast.
class HitsLease {
 public:
  HitsLease(const HitsLease&) = delete;
  HitsLease& operator=(const HitsLease&) = delete;
  HitsLease(HitsLease&& other) noexcept : hits_(std::move(other.hits_)) {}
  ~HitsLease();  // back to the pool
  RayHits& operator*() const { return *hits_; }
  RayHits* operator->() const { return hits_.get(); }

 private:
  friend HitsLease scratchHits(int width, int height);
  explicit HitsLease(std::unique_ptr<RayHits> hits) : hits_(std::move(hits)) {}
  std::unique_ptr<RayHits> hits_;
};
HitsLease scratchHits(int width, int height);
// Buffers in the pool now (leased or free), over all sizes: for tests and diagnostics.
std::size_t scratchHitsPooled();

// Optional per-ray far limit for cast(): a ray stops at range[i] + slack.at(range[i]), and a ray
// whose range[i] is not finite is not cast at all (its hit reads "nothing"). Correspondence search
// uses it: a surface farther than the measurement plus the threshold cannot pair with it.
struct CastLimit {
  const std::vector<float>* range = nullptr;
  RangeTolerance slack;
};

// A ray in the world frame, for incoherent casts (e.g. normal shooting).
struct WorldRay {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // unit
  float far;                  // the ray ends here (m)
};

// The point of a mesh's surface closest to a query point, in the mesh's own frame.
struct SurfacePoint {
  Eigen::Vector3f point;
  Eigen::Vector3f normal;  // unit face normal of the triangle (its winding's side)
  float distance;
};

// A triangle's plane: normal.dot(p) + offset = 0 (zero normal: degenerate triangle).
struct TrianglePlane {
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float offset = 0.0f;
};

struct RaycastSceneOptions {
  // Build quality of each mesh's BVH, built once per mesh: 0 low, 1 medium, 2 high.
  int object_build_quality = 2;
  int static_map_build_quality = 1;
};

class RaycastScene {
 public:
  explicit RaycastScene(const RaycastSceneOptions& options = {});
  ~RaycastScene();
  RaycastScene(const RaycastScene&) = delete;
  RaycastScene& operator=(const RaycastScene&) = delete;

  // Registers a mesh and builds its BVH; instances of it share that BVH.
  MeshId addMesh(std::shared_ptr<const TriangleMesh> mesh);
  const TriangleMesh& mesh(MeshId id) const;
  const Eigen::AlignedBox3f& meshBox(MeshId id) const;  // its bounding box, computed once
  std::size_t meshCount() const { return meshes_.size(); }

  // The static map (building) as node `node`, with the identity pose. Replaces a previous map.
  void setStaticMap(std::shared_ptr<const TriangleMesh> map, NodeId node);
  NodeId staticMapNode() const { return static_map_node_; }
  MeshId staticMapMesh() const { return static_map_mesh_; }  // -1 without a map

  // Instances are keyed by scene-graph node id; a node has at most one instance.
  void addInstance(NodeId node, MeshId mesh, const Eigen::Isometry3d& T_world_object);
  void setInstancePose(NodeId node, const Eigen::Isometry3d& T_world_object);
  void removeInstance(NodeId node);
  // A disabled instance is invisible to rays (e.g. to ask what lies behind an object).
  void setInstanceEnabled(NodeId node, bool enabled);
  // The nodes whose instances rays can hit now (the static map's among them).
  std::vector<NodeId> enabledInstances() const;
  bool hasInstance(NodeId node) const { return slot_of_node_.count(node) > 0; }
  std::size_t instanceCount() const { return slot_of_node_.size(); }
  Eigen::Isometry3d instancePose(NodeId node) const;
  MeshId instanceMesh(NodeId node) const;

  // Applies pending changes. Casting a scene with uncommitted changes throws.
  void commit();

  // Casts every ray of `tiles` (all rays by default) from the sensor pose into `hits`
  // (resized to the grid; rays outside the tiles are left untouched). Every cast ray gets its
  // range and node; its point, normal and primitive only as `attributes` asks (the others keep
  // older values), so that a caller that needs only what was hit where saves their work.
  void cast(const SensorRays& rays, const Eigen::Isometry3d& T_world_sensor, RayHits& hits,
            const TileSet* tiles = nullptr, const CastLimit& limit = {},
            unsigned attributes = kAllHitAttributes) const;
  // Casts world-frame rays; `hits` becomes a rays.size() x 1 grid.
  void cast(const std::vector<WorldRay>& rays, RayHits& hits) const;

  // Closest point of mesh `mesh` (in its own frame) to `p` no farther than `radius`, by an
  // Embree point query on the mesh's BVH; false when there is none. Thread-safe.
  bool closestPoint(MeshId mesh, const Eigen::Vector3f& p, float radius, SurfacePoint& out) const;

 private:
  struct Slot {
    NodeId node = kNoNode;
    MeshId mesh = -1;
    bool enabled = true;
    Eigen::Matrix3f R = Eigen::Matrix3f::Identity();  // for normals
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  };
  unsigned slotFor(NodeId node) const;
  unsigned attachInstance(NodeId node, MeshId mesh, const Eigen::Isometry3d& T);
  void writeTransform(unsigned slot, const Eigen::Isometry3d& T);
  void writeHit(const RTCRayHit16& rh, int lane, std::size_t i, RayHits& hits,
                unsigned attributes = kAllHitAttributes) const;

  RaycastSceneOptions options_;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* top_ = nullptr;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes_;
  std::vector<RTCSceneTy*> mesh_scenes_;
  std::vector<Eigen::AlignedBox3f> boxes_;          // per mesh
  std::vector<std::vector<TrianglePlane>> planes_;  // per mesh, per triangle (closest points)
  std::vector<Slot> slots_;                         // indexed by Embree geometry id (dense)
  std::vector<unsigned> free_slots_;
  std::unordered_map<NodeId, unsigned> slot_of_node_;
  NodeId static_map_node_ = kNoNode;
  MeshId static_map_mesh_ = -1;
  bool dirty_ = false;
};

}  // namespace sgt
