// PnP's distance replaced by the depth image's: a box seen by a simulated depth camera, a PnP pose
// with the right rotation but 15 cm too far along the ray, corrected to within the box's size.
#include <gtest/gtest.h>

#include "scene_graph_tracker/detection/depth_translation.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt::detection {
namespace {

TEST(DepthTranslation, PutsTheObjectAtTheMeasuredDistance) {
  const Eigen::Vector3f size(0.18f, 0.09f, 0.045f);  // multimeter-like
  RaycastScene scene;
  Eigen::Isometry3d T_camera_object = Eigen::Isometry3d::Identity();
  T_camera_object.linear() = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()))
                                 .toRotationMatrix();
  T_camera_object.translation() = Eigen::Vector3d(0.08, 0.05, 0.9);
  scene.addInstance(5, scene.addMesh(std::make_shared<TriangleMesh>(makeBox(size))),
                    T_camera_object);
  scene.commit();
  const PinholeModel cam;
  auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const SimulatedScan scan = simulate(scene, *rays, Eigen::Isometry3d::Identity());
  const RangeMeasurements depth =
      fromDepthImage(cam, rays, depthImage(scan, *rays), Eigen::Isometry3d::Identity());
  // The detection box: the projected corners' extent.
  const Eigen::AlignedBox3d box(-0.5 * size.cast<double>(), 0.5 * size.cast<double>());
  Detection d;
  d.box_min = Eigen::Vector2d::Constant(1e9), d.box_max = Eigen::Vector2d::Constant(-1e9);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector2d px =
        *cam.project(T_camera_object * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
    d.box_min = d.box_min.cwiseMin(px), d.box_max = d.box_max.cwiseMax(px);
  }
  Eigen::Isometry3d pnp = T_camera_object;
  pnp.translation() += 0.15 * pnp.translation().normalized();  // 15 cm too far along the ray
  const auto corrected = depthCorrectedPose(d, pnp, box, depth);
  ASSERT_TRUE(corrected);
  const double before = (pnp.translation() - T_camera_object.translation()).norm();
  const double after = (corrected->translation() - T_camera_object.translation()).norm();
  EXPECT_NEAR(before, 0.15, 1e-9);
  EXPECT_LT(after, 0.01)
      << "the median surface plus the entry depth lands within 1 cm of the centre";
  EXPECT_TRUE(corrected->linear().isApprox(pnp.linear()));  // rotation kept
  // No depth in the box (a LiDAR-less, empty image): no correction.
  RangeMeasurements empty = depth;
  std::fill(empty.range.begin(), empty.range.end(), std::numeric_limits<float>::quiet_NaN());
  EXPECT_FALSE(depthCorrectedPose(d, pnp, box, empty));
}

}  // namespace
}  // namespace sgt::detection
