#include "scene_graph_tracker/geometry/polygon_triangulation.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace sgt {
namespace {

using Point2 = Eigen::Vector2d;

// Newell's normal: robust for non-convex and slightly non-planar polygons.
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3f>& c) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d a = c[i].cast<double>(), b = c[(i + 1) % c.size()].cast<double>();
    n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                         (a.x() - b.x()) * (a.y() + b.y()));
  }
  return n;
}

// Corners projected onto the plane of `normal`, oriented so the polygon runs counter-clockwise.
std::vector<Point2> project(const std::vector<Eigen::Vector3f>& c, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.normalized().cross(u);
  std::vector<Point2> p;
  p.reserve(c.size());
  for (const auto& x : c) p.emplace_back(u.dot(x.cast<double>()), v.dot(x.cast<double>()));
  return p;
}

double cross(const Point2& a, const Point2& b, const Point2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

bool inside(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

// Ear clipping over the ring `ring` of indices into `p` (counter-clockwise).
class EarClipper {
 public:
  explicit EarClipper(std::vector<Point2> p) : p_(std::move(p)) {
    for (int i = 0; i < static_cast<int>(p_.size()); ++i) ring_.push_back(i);
  }

  std::vector<std::array<int, 3>> run() {
    std::vector<std::array<int, 3>> out;
    std::size_t misses = 0;  // consecutive corners tried without finding an ear
    std::size_t i = 0;
    while (ring_.size() > 3 && misses < ring_.size()) {
      i %= ring_.size();
      if (isEar(i)) {
        out.push_back({at(i + ring_.size() - 1), at(i), at(i + 1)});
        ring_.erase(ring_.begin() + static_cast<long>(i));
        misses = 0;
        i += ring_.size() - 1;  // step back: the previous corner may have become an ear
      } else {
        ++misses;
        ++i;
      }
    }
    for (std::size_t k = 1; k + 1 < ring_.size(); ++k)  // the last triangle, or a fan when stuck
      out.push_back({ring_[0], ring_[k], ring_[k + 1]});
    return out;
  }

 private:
  int at(std::size_t k) const { return ring_[k % ring_.size()]; }

  bool isEar(std::size_t k) const {
    const int a = at(k + ring_.size() - 1), b = at(k), c = at(k + 1);
    if (cross(p_[a], p_[b], p_[c]) <= 0.0) return false;  // reflex or collinear corner
    for (int j : ring_)
      if (j != a && j != b && j != c && p_[j] != p_[a] && p_[j] != p_[b] && p_[j] != p_[c] &&
          inside(p_[j], p_[a], p_[b], p_[c]))
        return false;
    return true;
  }

  std::vector<Point2> p_;
  std::vector<int> ring_;
};

}  // namespace

std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<Eigen::Vector3f>& corners) {
  const std::size_t n = corners.size();
  if (n < 3 || n > kMaxPolygonCorners)
    throw std::invalid_argument("a polygon of " + std::to_string(n) + " corners (3 to " +
                                std::to_string(kMaxPolygonCorners) + " are accepted)");
  if (n == 3) return {{0, 1, 2}};
  const Eigen::Vector3d normal = newellNormal(corners);
  std::vector<std::array<int, 3>> fan;
  if (!(normal.norm() > 0.0)) {  // no area (or not finite): a fan keeps the count and winding
    for (int k = 1; k + 1 < static_cast<int>(n); ++k) fan.push_back({0, k, k + 1});
    return fan;
  }
  return EarClipper(project(corners, normal)).run();
}

}  // namespace sgt
