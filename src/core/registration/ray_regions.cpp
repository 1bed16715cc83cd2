#include "scene_graph_tracker/registration/ray_regions.hpp"

#include <algorithm>
#include <cmath>

namespace sgt {
namespace {

std::vector<Eigen::Vector3d> cornersInSensor(const ObjectExtent& o,
                                             const Eigen::Isometry3d& T_sensor_world,
                                             float margin) {
  const Eigen::Vector3f lo = o.box.min() - Eigen::Vector3f::Constant(margin);
  const Eigen::Vector3f hi = o.box.max() + Eigen::Vector3f::Constant(margin);
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                            (c & 4) ? hi.z() : lo.z());
    out.push_back(T_sensor_world * o.T_world_object * p);
  }
  return out;
}

void pinholeRect(const PinholeModel& cam, const std::vector<Eigen::Vector3d>& corners,
                 std::vector<GridRect>& out) {
  int behind = 0;
  double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
  for (const auto& p : corners) {
    if (p.z() < 0.01) {
      ++behind;
      continue;
    }
    const auto px = cam.project(p);
    u0 = std::min(u0, px->x()), u1 = std::max(u1, px->x());
    v0 = std::min(v0, px->y()), v1 = std::max(v1, px->y());
  }
  if (behind == 8) return;
  if (behind > 0) {  // straddles the image plane: the object may be anywhere in view
    out.push_back({0, 0, cam.width, cam.height});
    return;
  }
  const auto clampi = [](double v, int hi) {
    return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi)));
  };
  GridRect r{clampi(std::floor(u0), cam.width), clampi(std::floor(v0), cam.height),
             clampi(std::ceil(u1) + 1, cam.width), clampi(std::ceil(v1) + 1, cam.height)};
  if (r.x0 < r.x1 && r.y0 < r.y1) out.push_back(r);
}

void lidarRects(const SpinningLidarModel& l, const std::vector<Eigen::Vector3d>& corners,
                std::vector<GridRect>& out) {
  // Azimuths relative to the centre's azimuth so the span never wraps inside the computation.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : corners) centre += p / 8.0;
  const double a_c = std::atan2(centre.y(), centre.x());
  double da0 = 0, da1 = 0, e0 = 1e9, e1 = -1e9;
  bool contains_sensor = true;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = 1e9, hi = -1e9;
    for (const auto& p : corners) lo = std::min(lo, p[axis]), hi = std::max(hi, p[axis]);
    contains_sensor &= lo <= 0.0 && hi >= 0.0;
  }
  if (contains_sensor) {
    out.push_back({0, 0, l.columns, l.rings});
    return;
  }
  for (const auto& p : corners) {
    const double da = std::remainder(std::atan2(p.y(), p.x()) - a_c, 2.0 * M_PI);
    da0 = std::min(da0, da), da1 = std::max(da1, da);
    const double e = std::atan2(p.z(), std::hypot(p.x(), p.y()));
    e0 = std::min(e0, e), e1 = std::max(e1, e);
  }
  const double phi_inc = l.phiInc() > 0 ? l.phiInc() : 1.0;
  const int r0 = std::max(0, static_cast<int>(std::floor((e0 - l.phi_min) / phi_inc)));
  const int r1 = std::min(l.rings, static_cast<int>(std::ceil((e1 - l.phi_min) / phi_inc)) + 1);
  if (r0 >= r1) return;
  const double c0 = (a_c + da0 - l.theta_min) / l.theta_inc,
               c1 = (a_c + da1 - l.theta_min) / l.theta_inc;
  int start = static_cast<int>(std::floor(c0));
  const int span = static_cast<int>(std::ceil(c1)) + 1 - start;
  if (span >= l.columns) {
    out.push_back({0, r0, l.columns, r1});
    return;
  }
  start = ((start % l.columns) + l.columns) % l.columns;
  out.push_back({start, r0, std::min(start + span, l.columns), r1});
  if (start + span > l.columns) out.push_back({0, r0, start + span - l.columns, r1});
}

void sphereRects(const SensorRays& rays, const std::vector<Eigen::Vector3d>& corners,
                 std::vector<GridRect>& out) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : corners) c += p / 8.0;
  double r2 = 0;
  for (const auto& p : corners) r2 = std::max(r2, (p - c).squaredNorm());
  const Eigen::Vector3f cf = c.cast<float>();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3f o = rays.origins.empty() ? Eigen::Vector3f::Zero() : rays.origins[i];
    const Eigen::Vector3f oc = cf - o;
    const float along = std::max(0.0f, oc.dot(rays.directions[i]));
    if ((oc - along * rays.directions[i]).squaredNorm() <= r2) {
      const int x = static_cast<int>(i % rays.width), y = static_cast<int>(i / rays.width);
      out.push_back({x, y, x + 1, y + 1});
    }
  }
}

}  // namespace

std::vector<GridRect> raysNearObjects(const RangeMeasurements& m,
                                      const std::vector<ObjectExtent>& objects, float margin_m) {
  std::vector<GridRect> rects;
  const Eigen::Isometry3d T_sensor_world = m.T_world_sensor.inverse();
  for (const auto& o : objects) {
    const auto corners = cornersInSensor(o, T_sensor_world, margin_m);
    if (const auto* cam = std::get_if<PinholeModel>(&m.model)) {
      pinholeRect(*cam, corners, rects);
    } else if (const auto* lidar = std::get_if<SpinningLidarModel>(&m.model)) {
      lidarRects(*lidar, corners, rects);
    } else {
      sphereRects(*m.rays, corners, rects);
    }
  }
  return rects;
}

ObjectSampling sampleRaysNearObjects(const RangeMeasurements& m,
                                     const std::vector<ObjectExtent>& objects,
                                     const RaySampling& sampling) {
  ObjectSampling out;
  const int max_rays = sampling.max_rays;
  const bool bounded = max_rays > 0 && std::holds_alternative<PinholeModel>(m.model);
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const float margin = sampling.margins ? (*sampling.margins)[k] : sampling.margin_m;
    const std::vector<GridRect> rects = sampling.skip && (*sampling.skip)[k]
                                            ? std::vector<GridRect>{}
                                            : raysNearObjects(m, {objects[k]}, margin);
    long long area = 0;
    for (const GridRect& r : rects)
      area += static_cast<long long>(r.x1 - r.x0) * static_cast<long long>(r.y1 - r.y0);
    const int base = std::max(1, sampling.stride);
    int s = base;
    // What to bound: the rays that reach the object (as seen at the base stride) when known, else
    // the region's: an object mostly hidden keeps the rays its few visible pixels give.
    const double known = sampling.on_object ? (*sampling.on_object)[k] : -1.0;
    const double cells = known >= 0.0 ? known * base * base : static_cast<double>(area);
    // The smallest stride whose grid holds at most max_rays of the cells: between powers of two
    // the count would fall by up to 4x at a threshold (an object just past it lost the fit's rays).
    if (bounded && cells > static_cast<double>(max_rays) * s * s)
      s = static_cast<int>(std::ceil(std::sqrt(cells / static_cast<double>(max_rays))));
    for (const GridRect& r : rects) out.regions.push_back({r, s});
    const float f = static_cast<float>(s) / static_cast<float>(base);
    out.weight.push_back(f * f);
  }
  return out;
}

namespace {

// Whether the segment o + s d, s in [0, length], meets `box` (slab test).
bool segmentMeetsBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float length,
                     const Eigen::AlignedBox3f& box) {
  float lo = 0.0f, hi = length;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12f) {
      if (o[a] < box.min()[a] || o[a] > box.max()[a]) return false;
      continue;
    }
    const float inv = 1.0f / d[a];
    float t0 = (box.min()[a] - o[a]) * inv, t1 = (box.max()[a] - o[a]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0), hi = std::min(hi, t1);
    if (lo > hi) return false;
  }
  return true;
}

// Slack around a mesh's box for the hit test: a hit found in float instance coordinates may lie
// a rounding error outside the box computed from the mesh.
constexpr float kBoxSlack = 1e-3f;

}  // namespace

PairableRays::PairableRays(const RangeMeasurements& m, const std::vector<ObjectExtent>& objects,
                           const std::vector<float>& margins, const std::vector<char>* skip,
                           const RangeTolerance& cast_slack)
    : m_(m), slack_(cast_slack) {
  for (std::size_t k = 0; k < objects.size(); ++k) {
    if (skip && (*skip)[k]) continue;
    const Eigen::Isometry3f T =
        (objects[k].T_world_object.inverse() * m.T_world_sensor).cast<float>();
    const Eigen::AlignedBox3f& b = objects[k].box;
    const Eigen::Vector3f grow = Eigen::Vector3f::Constant(kBoxSlack + margins[k]);
    targets_.push_back({T.linear(), T.translation(),
                        Eigen::AlignedBox3f(b.min() - Eigen::Vector3f::Constant(kBoxSlack),
                                            b.max() + Eigen::Vector3f::Constant(kBoxSlack)),
                        Eigen::AlignedBox3f(b.min() - grow, b.max() + grow),
                        raysNearObjects(m, {objects[k]}, margins[k])});
  }
}

bool PairableRays::operator()(std::size_t i) const {
  if (!m_.valid(i)) return false;
  const SensorRays& rays = *m_.rays;
  const float r = m_.range[i];
  const float length = r + slack_.at(r);
  const int x = static_cast<int>(i % rays.width), y = static_cast<int>(i / rays.width);
  for (const Target& t : targets_) {
    if (std::none_of(t.rects.begin(), t.rects.end(), [&](const GridRect& g) {
          return x >= g.x0 && x < g.x1 && y >= g.y0 && y < g.y1;
        }))
      continue;
    const Eigen::Vector3f o =
        rays.origins.empty() ? t.t : Eigen::Vector3f(t.R * rays.origins[i] + t.t);
    const Eigen::Vector3f d = t.R * rays.directions[i];
    if (t.pull_box.contains(o + d * r) || segmentMeetsBox(o, d, length, t.hit_box)) return true;
  }
  return false;
}

}  // namespace sgt
