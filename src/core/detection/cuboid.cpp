#include "scene_graph_tracker/detection/cuboid.hpp"

namespace sgt::detection {

std::array<Eigen::Vector3d, kCuboidKeypoints> cuboidKeypoints(const Eigen::AlignedBox3d& box) {
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  // x sign, y sign per corner of a face (TopRight, TopLeft, BottomLeft, BottomRight).
  static constexpr int kX[4] = {+1, -1, -1, +1};
  static constexpr int kY[4] = {+1, +1, -1, -1};
  std::array<Eigen::Vector3d, kCuboidKeypoints> k;
  for (int face = 0; face < 2; ++face) {
    const double z = face == 0 ? hi.z() : lo.z();
    for (int c = 0; c < 4; ++c) {
      k[face * 4 + c] =
          Eigen::Vector3d(kX[c] > 0 ? hi.x() : lo.x(), kY[c] > 0 ? hi.y() : lo.y(), z);
    }
  }
  k[8] = box.center();
  return k;
}

std::array<Eigen::Vector3d, kCuboidKeypoints> cuboidKeypoints(
    const Eigen::AlignedBox3d& box_model, const Eigen::Isometry3d& T_model_object) {
  auto k = cuboidKeypoints(box_model);
  const Eigen::Isometry3d T_object_model = T_model_object.inverse();
  for (auto& p : k) p = T_object_model * p;
  return k;
}

}  // namespace sgt::detection
