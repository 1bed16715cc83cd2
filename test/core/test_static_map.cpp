// The static map from a URDF (boxes, cylinders, spheres, meshes with origins and joints) and from
// a plain mesh file, checked by casting rays at where each part must be.
#include <gtest/gtest.h>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"
#include "support.hpp"

namespace sgt {
namespace {

const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="lab">
  <link name="floor">
    <visual><origin xyz="0 0 -0.05"/><geometry><box size="10 10 0.1"/></geometry></visual>
  </link>
  <joint name="floor_to_table" type="fixed">
    <parent link="floor"/><child link="table"/><origin xyz="2 0 0" rpy="0 0 1.5707963"/>
  </joint>
  <link name="table">
    <visual><origin xyz="0 0 0.75"/><geometry><box size="1.6 0.8 0.04"/></geometry></visual>
    <visual><origin xyz="0.5 0 1.0"/><geometry><sphere radius="0.1"/></geometry></visual>
  </link>
  <joint name="floor_to_pillar" type="fixed">
    <parent link="floor"/><child link="pillar"/><origin xyz="-3 0 0"/>
  </joint>
  <link name="pillar">
    <visual><origin xyz="0 0 1.5"/><geometry><cylinder radius="0.2" length="3"/></geometry></visual>
  </link>
  <joint name="floor_to_part" type="fixed">
    <parent link="floor"/><child link="part"/><origin xyz="0 -3 0"/>
  </joint>
  <link name="part">
    <visual><origin xyz="0 0 0"/><geometry><mesh filename="tet.obj" scale="2 2 2"/></geometry></visual>
  </link>
</robot>
)";

float rangeAlong(const RaycastScene& scene, const Eigen::Vector3d& origin,
                 const Eigen::Vector3f& dir) {
  RayHits hits;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = origin;
  scene.cast(makeRays({dir}), T, hits);
  return hits.range[0];
}

TEST(StaticMap, FromUrdf) {
  test::writeFile("tet.obj",
                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const std::string path = test::writeFile("lab.urdf", kUrdf);
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(loadStaticMap(path)), 1);
  scene.commit();
  const Eigen::Vector3f down(0, 0, -1);
  EXPECT_NEAR(rangeAlong(scene, {4, 4, 2}, down), 2.0f, 1e-5f);  // floor top at z = 0
  EXPECT_NEAR(rangeAlong(scene, {2, 0.7, 2}, down), 1.23f,
              1e-5f);  // table (rotated 90 deg) top at 0.77
  EXPECT_NEAR(rangeAlong(scene, {2, 0.9, 2}, down), 2.0f,
              1e-5f);  // beyond the table's 0.8 m half-length
  // The sphere sits 0.5 m along the table's x axis, which the joint turned to world +y.
  EXPECT_NEAR(rangeAlong(scene, {2, 0.5, 2}, down), 0.9f, 2e-3f);
  EXPECT_NEAR(rangeAlong(scene, {-5, 0, 1}, {1, 0, 0}), 1.8f, 2e-3f);  // pillar r 0.2 at x = -3
  EXPECT_NEAR(rangeAlong(scene, {0.5, -2.5, 3}, down), 3.0f - 1.0f,
              1e-4f);  // tet scaled 2: x+y+z=2
}

TEST(StaticMap, Errors) {
  EXPECT_THROW(loadStaticMap("/nonexistent/lab.urdf"), MeshError);
  const std::string bad = test::writeFile("bad.urdf", "<robot name='x'><link name='a'></robot>");
  EXPECT_THROW(loadStaticMap(bad), MeshError);
  const std::string missing_mesh =
      test::writeFile("missing.urdf",
                      "<robot name='x'><link name='a'><visual><geometry><mesh "
                      "filename='gone.stl'/></geometry></visual></link></robot>");
  try {
    loadStaticMap(missing_mesh);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("link 'a'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gone.stl"), std::string::npos) << e.what();
  }
}

TEST(StaticMap, FromMeshFile) {
  const std::string path = test::writeFile(
      "map.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  EXPECT_EQ(loadStaticMap(path).triangleCount(), 4u);
}

}  // namespace
}  // namespace sgt
