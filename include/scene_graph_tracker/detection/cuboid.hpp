// The cuboid keypoints of an object class in DOPE's order, shared by the detector's PnP, the
// training-data renderer and the evaluation, so that every part means the same corner by index k.
//
// DOPE (NVlabs/Deep_Object_Pose, cuboid.py) with width along x, height along y, depth along z of
// the box:  0 FrontTopRight (+x +y +z), 1 FrontTopLeft (-x +y +z), 2 FrontBottomLeft (-x -y +z),
// 3 FrontBottomRight (+x -y +z), 4..7 the same on the rear face (-z), 8 the centre.
#pragma once

#include <Eigen/Geometry>
#include <array>

namespace sgt::detection {

constexpr int kCuboidKeypoints = 9;

// The nine keypoints (object frame) of an axis-aligned box given in the object frame.
std::array<Eigen::Vector3d, kCuboidKeypoints> cuboidKeypoints(const Eigen::AlignedBox3d& box);

// The box of a class in the frame the detector reports poses in: `T_model_object` maps object
// coordinates to the model frame the keypoints were trained in (identity for the package's own
// meshes; the pbr_objects KLT has a 90 degree model transform, see model_transforms.yaml).
// Keypoints in the object frame: T_model_object^-1 applied to the model-frame corners.
std::array<Eigen::Vector3d, kCuboidKeypoints> cuboidKeypoints(
    const Eigen::AlignedBox3d& box_model, const Eigen::Isometry3d& T_model_object);

}  // namespace sgt::detection
