// Labels of the keypoint detector's training data, shared by the dataset renderer and the
// evaluation: the symmetry-canonical pose of an object and its projected cuboid keypoints.
//
// A symmetric object (screwdriver about x, KLT 180 degrees about z) looks the same under
// T * S for every symmetry S, so its corners have no unique labels. The label pose is the
// T * S whose camera-frame rotation is closest (geodesic angle) to a fixed canonical rotation:
// object x along camera x, object y along camera -y, object z towards the camera.
#pragma once

#include <array>

#include "scene_graph_tracker/detection/cuboid.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt::detection {

// The canonical camera-frame rotation: diag(1, -1, -1).
Eigen::Matrix3d canonicalLabelRotation();

// Among T_camera_object * S, S in symmetry.sampled(step), the one closest to the canonical
// rotation.
Eigen::Isometry3d canonicalSymmetricPose(const Eigen::Isometry3d& T_camera_object,
                                         const Symmetry& symmetry,
                                         double continuous_step_rad = 5.0 * M_PI / 180.0);

// The box's own turns: the identity and half turns about its x, y and z axes through its centre
// (object origins are box centres). Each maps the cuboid's corners onto themselves.
std::array<Eigen::Isometry3d, 4> boxHalfTurns();

// Cuboid labels: among T_camera_object * S * B (S the object's symmetries, B in boxHalfTurns())
// the pose closest to the canonical rotation. The keypoints then follow from the cuboid's outline
// alone, so an object whose twins differ in small details only (the material box and its latch,
// the multimeter) gets one label for what the image shows instead of two that a regression
// averages into the box centre. PnP on such keypoints finds the pose up to a box half turn;
// the tracker's orientation search picks the turn that explains the depth.
Eigen::Isometry3d canonicalCuboidPose(const Eigen::Isometry3d& T_camera_object,
                                      const Symmetry& symmetry,
                                      double continuous_step_rad = 5.0 * M_PI / 180.0);

struct CuboidProjection {
  std::array<Eigen::Vector2d, kCuboidKeypoints>
      uv;  // pixels, centres at integers (0, 0 when not inside)
  std::array<bool, kCuboidKeypoints> inside{};  // in front of the camera and inside the image
};

// The cuboid keypoints of `box` (object frame) under T_camera_object, projected by `camera`.
CuboidProjection projectCuboid(const PinholeModel& camera, const Eigen::Isometry3d& T_camera_object,
                               const Eigen::AlignedBox3d& box);

}  // namespace sgt::detection
