#include "scene_graph_tracker/sensors/sensor_models.hpp"

#include <stdexcept>
#include <string>

namespace sgt {

Eigen::Isometry3d opticalLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  return T;
}

Eigen::Vector3f PinholeModel::direction(int u, int v) const {
  const Eigen::Vector2d pixel((u - cx) / fx, (v - cy) / fy);  // normalised, distorted
  Eigen::Vector2d xy = pixel;
  if (distorted()) {
    // The undistorted point whose distortion is the pixel, by OpenCV's fixed-point iteration
    // (undistortPoints), run to convergence.
    const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3],
                 k3 = distortion[4];
    for (int i = 0; i < 50; ++i) {
      const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
      const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
      const Eigen::Vector2d tangential(2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                                       p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
      const Eigen::Vector2d next = (pixel - tangential) / radial;
      const double moved = (next - xy).squaredNorm();
      xy = next;
      if (moved < 1e-24) break;
    }
  }
  return Eigen::Vector3f(static_cast<float>(xy.x()), static_cast<float>(xy.y()), 1.0f).normalized();
}

SensorRays makeRays(const PinholeModel& m) {
  if (m.width <= 0 || m.height <= 0 || !(m.fx > 0) || !(m.fy > 0))
    throw std::invalid_argument("pinhole model needs positive width, height, fx, fy (got " +
                                std::to_string(m.width) + "x" + std::to_string(m.height) + ", fx " +
                                std::to_string(m.fx) + ", fy " + std::to_string(m.fy) + ")");
  SensorRays rays;
  rays.width = m.width;
  rays.height = m.height;
  rays.range_min = m.range_min;
  rays.range_max = m.range_max;
  rays.directions.resize(static_cast<std::size_t>(m.width) * m.height);
  for (int v = 0; v < m.height; ++v)
    for (int u = 0; u < m.width; ++u) rays.directions[rays.index(u, v)] = m.direction(u, v);
  return rays;
}

std::shared_ptr<const SensorRays> PinholeRayCache::rays(const PinholeModel& m) {
  const bool same = rays_ && m.width == model_.width && m.height == model_.height &&
                    m.fx == model_.fx && m.fy == model_.fy && m.cx == model_.cx &&
                    m.cy == model_.cy && m.distortion == model_.distortion &&
                    m.range_min == model_.range_min && m.range_max == model_.range_max;
  if (!same) rays_ = std::make_shared<const SensorRays>(makeRays(m)), model_ = m;
  return rays_;
}

SensorRays makeRays(const SpinningLidarModel& m) {
  if (m.columns <= 0 || m.rings <= 0)
    throw std::invalid_argument("LiDAR model needs positive columns and rings (got " +
                                std::to_string(m.columns) + " x " + std::to_string(m.rings) + ")");
  SensorRays rays;
  rays.width = m.columns;
  rays.height = m.rings;
  rays.range_min = m.range_min;
  rays.range_max = m.range_max;
  rays.directions.resize(static_cast<std::size_t>(m.columns) * m.rings);
  for (int r = 0; r < m.rings; ++r)
    for (int c = 0; c < m.columns; ++c) rays.directions[rays.index(c, r)] = m.direction(c, r);
  return rays;
}

SensorRays makeRays(std::vector<Eigen::Vector3f> directions, std::vector<Eigen::Vector3f> origins,
                    float range_min, float range_max) {
  if (!origins.empty() && origins.size() != directions.size())
    throw std::invalid_argument("ray set: " + std::to_string(origins.size()) + " origins for " +
                                std::to_string(directions.size()) + " directions");
  for (auto& d : directions) {
    const float n = d.norm();
    if (!(n > 0.0f) || !std::isfinite(n))
      throw std::invalid_argument("ray set: a direction is zero or not finite");
    d /= n;
  }
  SensorRays rays;
  rays.width = static_cast<int>(directions.size());
  rays.height = directions.empty() ? 0 : 1;
  rays.directions = std::move(directions);
  rays.origins = std::move(origins);
  rays.range_min = range_min;
  rays.range_max = range_max;
  return rays;
}

}  // namespace sgt
