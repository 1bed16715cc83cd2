// Ray casting on Embree: analytic hits on boxes and spheres, world normals of rotated
// instances, shared meshes, moving / removing / disabling instances, tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <thread>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"

namespace sgt {
namespace {

Eigen::Isometry3d at(const Eigen::Vector3d& t,
                     const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

// One ray from the origin along `dir` (world frame).
RayHits castOne(const RaycastScene& scene, const Eigen::Vector3f& origin,
                const Eigen::Vector3f& dir) {
  const SensorRays rays = makeRays({dir});
  RayHits hits;
  scene.cast(rays, at(origin.cast<double>()), hits);
  return hits;
}

TEST(RaycastScene, BoxRangeAndNormal) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.4f, 0.6f})));
  scene.addInstance(7, box, at({2, 0, 0}));
  scene.commit();
  const RayHits h = castOne(scene, {0, 0, 0}, {1, 0, 0});
  ASSERT_EQ(h.node[0], 7);
  EXPECT_NEAR(h.range[0], 1.9f, 1e-5f);
  EXPECT_TRUE(h.point[0].isApprox(Eigen::Vector3f(1.9f, 0, 0), 1e-5f));
  EXPECT_TRUE(h.normal[0].isApprox(Eigen::Vector3f(-1, 0, 0), 1e-5f));
  const RayHits miss = castOne(scene, {0, 0, 0}, {0, 1, 0});
  EXPECT_EQ(miss.node[0], kNoNode);
  EXPECT_TRUE(std::isinf(miss.range[0]));
}

TEST(RaycastScene, SphereRangeAndNormalMatchAnalytic) {
  RaycastScene scene;
  const float radius = 0.5f;
  const MeshId sphere = scene.addMesh(std::make_shared<TriangleMesh>(makeSphere(radius, 256, 128)));
  const Eigen::Vector3f c(3, 1, 0.5f);
  scene.addInstance(3, sphere, at(c.cast<double>()));
  scene.commit();
  for (float off : {0.0f, 0.2f, 0.4f}) {
    const Eigen::Vector3f o(0, 1 + off, 0.5f);
    const RayHits h = castOne(scene, o, {1, 0, 0});
    ASSERT_EQ(h.node[0], 3);
    const float expected = c.x() - std::sqrt(radius * radius - off * off);
    // The tessellation (256 x 128) lies inside the sphere by at most r(1 - cos(pi/128)) = 0.15 mm.
    EXPECT_NEAR(h.range[0], expected, 6e-4f) << off;
    const Eigen::Vector3f n_true = (h.point[0] - c).normalized();
    EXPECT_GT(h.normal[0].dot(n_true), std::cos(2.0 * M_PI / 128)) << off;
  }
}

TEST(RaycastScene, RotatedInstanceGivesWorldNormals) {
  // Embree's Ng is in object space: the scene must rotate it into the world.
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.2f, 0.2f})));
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  scene.addInstance(1, box, at({2, 0, 0}, R));
  scene.commit();
  // Look at the box's -x face straight along its (rotated) world normal.
  const Eigen::Vector3f n_face =
      (R * Eigen::Vector3d(-1, 0, 0)).cast<float>();  // world normal of the -x face
  const Eigen::Vector3f origin = Eigen::Vector3f(2, 0, 0) + 1.0f * n_face;
  const RayHits h = castOne(scene, origin, -n_face);
  ASSERT_EQ(h.node[0], 1);
  EXPECT_NEAR(h.range[0], 0.9f, 1e-5f);
  EXPECT_TRUE(h.normal[0].isApprox(n_face, 1e-5f)) << h.normal[0].transpose();
  EXPECT_NEAR(h.normal[0].norm(), 1.0f, 1e-6f);
}

TEST(RaycastScene, ManyInstancesShareOneMesh) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.1f, 0.1f, 0.1f})));
  for (int i = 0; i < 100; ++i) scene.addInstance(100 + i, box, at({1.0 + i, 0, 0}));
  scene.commit();
  EXPECT_EQ(scene.meshCount(), 1u);
  EXPECT_EQ(scene.instanceCount(), 100u);
  // A row of rays along y at x = 1 + 5 hits only instance 105.
  const RayHits h = castOne(scene, {6, -2, 0}, {0, 1, 0});
  EXPECT_EQ(h.node[0], 105);
  EXPECT_NEAR(h.range[0], 1.95f, 1e-5f);
}

TEST(RaycastScene, MovingRemovingAndDisablingInstances) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.2f, 0.2f})));
  scene.addInstance(1, box, at({2, 0, 0}));
  scene.addInstance(2, box, at({4, 0, 0}));
  scene.commit();
  EXPECT_EQ(castOne(scene, {0, 0, 0}, {1, 0, 0}).node[0], 1);

  scene.setInstancePose(1, at({2, 5, 0}));
  EXPECT_THROW(castOne(scene, {0, 0, 0}, {1, 0, 0}), std::logic_error);  // not committed
  scene.commit();
  RayHits h = castOne(scene, {0, 0, 0}, {1, 0, 0});
  EXPECT_EQ(h.node[0], 2);
  EXPECT_NEAR(h.range[0], 3.9f, 1e-5f);
  EXPECT_TRUE(scene.instancePose(1).translation().isApprox(Eigen::Vector3d(2, 5, 0)));

  scene.setInstanceEnabled(2, false);
  scene.commit();
  EXPECT_EQ(castOne(scene, {0, 0, 0}, {1, 0, 0}).node[0], kNoNode);
  scene.setInstanceEnabled(2, true);
  scene.removeInstance(1);
  scene.commit();
  EXPECT_FALSE(scene.hasInstance(1));
  EXPECT_THROW(scene.setInstancePose(1, at({0, 0, 0})), std::out_of_range);
  // The freed slot is reused by the next instance.
  scene.addInstance(9, box, at({1, 0, 0}));
  scene.commit();
  EXPECT_EQ(castOne(scene, {0, 0, 0}, {1, 0, 0}).node[0], 9);
  EXPECT_THROW(scene.addInstance(9, box, at({1, 0, 0})), std::invalid_argument);
  Eigen::Isometry3d bad = at({0, 0, 0});
  bad.translation().x() = std::nan("");
  EXPECT_THROW(scene.setInstancePose(9, bad), std::invalid_argument);
}

TEST(RaycastScene, StaticMapAndObjectsTogether) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})), 1);  // floor slab
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.2f, 0.2f})));
  scene.addInstance(5, box, at({0, 0, 0.15}));
  scene.commit();
  EXPECT_EQ(castOne(scene, {0, 0, 2}, {0, 0, -1}).node[0], 5);
  const RayHits h = castOne(scene, {1, 0, 2}, {0, 0, -1});
  EXPECT_EQ(h.node[0], 1);
  EXPECT_NEAR(h.range[0], 1.95f, 1e-5f);
  EXPECT_TRUE(h.normal[0].isApprox(Eigen::Vector3f::UnitZ(), 1e-6f));
  EXPECT_EQ(scene.staticMapNode(), 1);
}

TEST(RaycastScene, TilesCoverExactlyTheRequestedRegion) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})), 1);
  scene.commit();
  PinholeModel cam;
  cam.width = 64, cam.height = 48, cam.fx = cam.fy = 50, cam.cx = 31.5, cam.cy = 23.5;
  const SensorRays rays = makeRays(cam);
  const TileSet tiles = TileSet::covering(rays, {{10, 10, 13, 11}, {60, 40, 70, 50}});
  // {10..13}x{10} lies in tiles x 2..3, y 2: two tiles; {60..64}x{40..48}: tiles x 15, y 10..11.
  EXPECT_EQ(tiles.tiles().size(), 4u);
  RayHits hits;
  const Eigen::Isometry3d T =
      at({0, 0, 2}, Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix());
  scene.cast(rays, T, hits, &tiles);
  std::size_t visited = 0;
  tiles.forEachRay(rays, [&](std::size_t i) {
    ++visited;
    EXPECT_EQ(hits.node[i], 1);
  });
  EXPECT_EQ(visited, 64u);
  EXPECT_EQ(hits.node[0], kNoNode);  // outside the tiles: untouched
}

TEST(RaycastScene, StridedTilesCastEveryOtherRay) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})), 1);
  scene.commit();
  PinholeModel cam;
  cam.width = 64, cam.height = 48, cam.fx = cam.fy = 50, cam.cx = 31.5, cam.cy = 23.5;
  const SensorRays rays = makeRays(cam);
  // Stride 2: a tile spans 8x8 pixels; {0..16}x{0..8} is two tiles of 16 rays, at even x and y.
  const TileSet tiles = TileSet::covering(rays, {{0, 0, 16, 8}}, 2);
  EXPECT_EQ(tiles.stride(), 2);
  EXPECT_EQ(tiles.rayCount(), 32u);
  RayHits hits;
  scene.cast(rays,
             at({0, 0, 2}, Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix()),
             hits, &tiles);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      EXPECT_EQ(hits.node[rays.index(x, y)], (x % 2 == 0 && y % 2 == 0) ? 1 : kNoNode)
          << x << "," << y;
}

TEST(RaycastScene, RangeLimitStopsRaysAndSkipsInvalidOnes) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.4f, 0.6f})));
  scene.addInstance(7, box, at({2, 0, 0}));  // front face at 1.9 m
  scene.commit();
  const SensorRays rays = makeRays({{1, 0, 0}, {1, 0, 0}, {1, 0, 0}});
  const std::vector<float> limit = {1.85f, 1.88f, std::numeric_limits<float>::quiet_NaN()};
  RayHits hits;
  scene.cast(rays, Eigen::Isometry3d::Identity(), hits, nullptr, CastLimit{&limit, 0.03f});
  EXPECT_EQ(hits.node[0], kNoNode);  // stops at 1.88 m, before the face
  EXPECT_EQ(hits.node[1], 7);        // reaches 1.91 m
  EXPECT_NEAR(hits.range[1], 1.9f, 1e-5f);
  EXPECT_EQ(hits.node[2], kNoNode);  // no measurement: not cast
  const std::vector<float> wrong_size = {1.0f};
  EXPECT_THROW(
      scene.cast(rays, Eigen::Isometry3d::Identity(), hits, nullptr, CastLimit{&wrong_size, 0.0f}),
      std::invalid_argument);
}

TEST(RaycastScene, WorldRaysHitLikeSensorRays) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.4f, 0.6f})));
  scene.addInstance(7, box, at({2, 0, 0}));
  scene.commit();
  std::vector<WorldRay> rays;
  for (int i = 0; i < 20; ++i)
    rays.push_back({{2.0f, 0.01f * i, 1.0f}, {0, 0, -1}, i < 10 ? 2.0f : 0.6f});
  RayHits hits;
  scene.cast(rays, hits);
  ASSERT_EQ(hits.size(), 20u);
  for (int i = 0; i < 20; ++i) {
    if (i < 10) {  // down onto the top face at z = 0.3
      ASSERT_EQ(hits.node[i], 7) << i;
      EXPECT_NEAR(hits.point[i].z(), 0.3f, 1e-5f);
      EXPECT_TRUE(hits.normal[i].isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f));
    } else {  // ends at z = 0.4, above the box
      EXPECT_EQ(hits.node[i], kNoNode) << i;
    }
  }
}

TEST(RaycastScene, ClosestPointOnAMeshWithinARadius) {
  RaycastScene scene;
  const MeshId box = scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.2f, 0.4f, 0.6f})));
  SurfacePoint sp;
  ASSERT_TRUE(scene.closestPoint(box, {0.15f, 0.05f, 0.1f}, 0.1f, sp));  // 5 cm outside the +x face
  EXPECT_TRUE(sp.point.isApprox(Eigen::Vector3f(0.1f, 0.05f, 0.1f), 1e-5f));
  EXPECT_NEAR(sp.distance, 0.05f, 1e-5f);
  EXPECT_NEAR(std::abs(sp.normal.x()), 1.0f, 1e-5f);
  ASSERT_TRUE(
      scene.closestPoint(box, {0.0f, 0.0f, 0.28f}, 0.1f, sp));  // inside, 2 cm below the top
  EXPECT_NEAR(sp.point.z(), 0.3f, 1e-5f);
  EXPECT_FALSE(
      scene.closestPoint(box, {0.5f, 0.0f, 0.0f}, 0.1f, sp));  // 40 cm away: beyond the radius
}

// Distance from p to segment ab.
float segmentDistance(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                      const Eigen::Vector3f& b) {
  const Eigen::Vector3f ab = b - a;
  const float t =
      ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.f, 1.f) : 0.f;
  return (a + t * ab - p).norm();
}

// Distance from p to triangle abc, by its plane when p projects inside, else by its edges.
float triangleDistance(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                       const Eigen::Vector3f& c) {
  const Eigen::Vector3f n = (b - a).cross(c - a);
  if (n.squaredNorm() > 0) {
    const Eigen::Vector3f q = p - n * ((p - a).dot(n) / n.squaredNorm());
    const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
    if (inside) return (q - p).norm();
  }
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

// The closest point query against a brute force over every triangle, on a sphere mesh (whose pole
// triangles are slivers) from points inside, outside and beyond the radius.
TEST(RaycastScene, ClosestPointMatchesABruteForceOverEveryTriangle) {
  const auto mesh = std::make_shared<TriangleMesh>(makeSphere(0.05f, 24, 12));
  RaycastScene scene;
  const MeshId id = scene.addMesh(mesh);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.09f, 0.09f);
  int found = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3f p(u(rng), u(rng), u(rng));
    float best = std::numeric_limits<float>::infinity();
    for (const Triangle& t : mesh->triangles)
      best = std::min(best, triangleDistance(p, mesh->vertices[t[0]], mesh->vertices[t[1]],
                                             mesh->vertices[t[2]]));
    SurfacePoint sp;
    const float radius = 0.02f;
    const bool hit = scene.closestPoint(id, p, radius, sp);
    if (best < radius - 1e-5f) {
      ASSERT_TRUE(hit) << i;
      EXPECT_NEAR(sp.distance, best, 1e-5f) << i;
      EXPECT_NEAR((sp.point - p).norm(), best, 1e-5f) << i;
      ++found;
    } else if (best > radius + 1e-5f) {
      EXPECT_FALSE(hit) << i;
    }
  }
  EXPECT_GT(found, 100);
}

}  // namespace
// Scratch hit buffers come from one pool: a buffer given back is lent again, whichever thread
// asks; two leases at once get two buffers; each size has its own.
TEST(RaycastScene, ScratchHitsAreLentFromOnePoolWhateverTheThread) {
  const std::size_t before = scratchHitsPooled();
  const RayHits* first = nullptr;
  {
    const HitsLease a = scratchHits(64, 48);
    EXPECT_EQ(a->size(), 64u * 48u);
    first = &*a;
    const HitsLease b = scratchHits(64, 48);  // while a is out
    EXPECT_NE(&*b, first);
    const HitsLease small = scratchHits(16, 1);
    EXPECT_EQ(small->size(), 16u);
  }
  EXPECT_EQ(scratchHitsPooled(), before + 3);
  for (int t = 0; t < 8; ++t)  // eight threads, one after the other: no new buffer
    std::thread([&] {
      const HitsLease again = scratchHits(64, 48);
      EXPECT_EQ(again->size(), 64u * 48u);
    }).join();
  EXPECT_EQ(scratchHitsPooled(), before + 3);
}

}  // namespace sgt
