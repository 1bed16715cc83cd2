// Oriented boxes and the three tests the spatial relations are made of: containment,
// intersection (separating axes) and the 3D distance between two boxes.
#pragma once

#include <Eigen/Geometry>
#include <array>

namespace sgt::relations {

// Centre frame: the box is T_world_box * [-half_extents, +half_extents].
struct OrientedBox {
  Eigen::Isometry3d T_world_box = Eigen::Isometry3d::Identity();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
};

// An object's box (its mesh's axis-aligned box in the object frame) moved by the object's pose.
OrientedBox orientedBox(const Eigen::AlignedBox3d& box_object,
                        const Eigen::Isometry3d& T_world_object);

// The 8 corners in the world frame; bit i of the corner index set = +half along axis i, else -half.
std::array<Eigen::Vector3d, 8> corners(const OrientedBox& b);
// The smallest box in `frame`'s orientation (centred where `b` is) that encloses `b`.
OrientedBox enclosingBox(const OrientedBox& b, const Eigen::Matrix3d& R_world_frame);

// All 8 corners of `inner` inside `outer` (closed box: corners on a face count as inside).
bool contains(const OrientedBox& outer, const OrientedBox& inner);
// Same, with corners allowed up to `tolerance` (m) outside `outer`.
bool contains(const OrientedBox& outer, const OrientedBox& inner, double tolerance);
// Separating-axis test over the 15 candidate axes; touching boxes intersect.
bool intersects(const OrientedBox& a, const OrientedBox& b);
// Smallest distance between the two solids; 0 when they intersect. Exact: the minimum over
// vertex-to-box distances both ways and edge-to-edge distances.
double distance(const OrientedBox& a, const OrientedBox& b);

}  // namespace sgt::relations
