#include "scene_graph_tracker/detection/depth_translation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sgt::detection {

std::optional<Eigen::Isometry3d> depthCorrectedPose(const Detection& detection,
                                                    const Eigen::Isometry3d& T_camera_object,
                                                    const Eigen::AlignedBox3d& box,
                                                    const RangeMeasurements& depth,
                                                    const DepthTranslationOptions& options) {
  const auto* cam = std::get_if<PinholeModel>(&depth.model);
  if (!cam || !depth.rays || depth.rays->width != cam->width || depth.rays->height != cam->height)
    return std::nullopt;
  const Eigen::Vector2d centre = 0.5 * (detection.box_min + detection.box_max);
  const Eigen::Vector2d half = 0.5 * options.box_fraction * (detection.box_max - detection.box_min);
  const int u0 = std::max(0, static_cast<int>(std::ceil(centre.x() - half.x())));
  const int u1 = std::min(cam->width - 1, static_cast<int>(std::floor(centre.x() + half.x())));
  const int v0 = std::max(0, static_cast<int>(std::ceil(centre.y() - half.y())));
  const int v1 = std::min(cam->height - 1, static_cast<int>(std::floor(centre.y() + half.y())));
  std::vector<float> ranges;
  for (int v = v0; v <= v1; ++v)
    for (int u = u0; u <= u1; ++u) {
      const auto i = static_cast<std::size_t>(depth.rays->index(u, v));
      if (depth.valid(i)) ranges.push_back(depth.range[i]);
    }
  if (static_cast<int>(ranges.size()) < options.min_pixels) return std::nullopt;
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
  const double surface = ranges[ranges.size() / 2];
  const Eigen::Vector3d ray =
      Eigen::Vector3d((centre.x() - cam->cx) / cam->fx, (centre.y() - cam->cy) / cam->fy, 1.0)
          .normalized();
  // From the box centre back along the ray to where the ray enters the turned box (slab test):
  // the surface the central pixels see.
  const Eigen::Vector3d in_object = (T_camera_object.linear().transpose() * ray).cwiseAbs();
  double half_depth = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    if (in_object[a] > 1e-9) half_depth = std::min(half_depth, 0.5 * box.sizes()[a] / in_object[a]);
  Eigen::Isometry3d T = T_camera_object;
  T.translation() = ray * (surface + half_depth) - T.linear() * box.center();
  return T;
}

}  // namespace sgt::detection
