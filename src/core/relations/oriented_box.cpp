#include "scene_graph_tracker/relations/oriented_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sgt::relations {
namespace {

// Distance from a world point to the solid box.
double pointDistance(const OrientedBox& b, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p = b.T_world_box.inverse() * p_world;
  const Eigen::Vector3d outside = (p.cwiseAbs() - b.half_extents).cwiseMax(0.0);
  return outside.norm();
}

// Squared distance between segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection 5.1.9).
double segmentDistance2(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1,
                        const Eigen::Vector3d& p2, const Eigen::Vector3d& q2) {
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double eps = 1e-18;
  double s = 0.0, t = 0.0;
  if (a <= eps && e <= eps) return r.squaredNorm();
  if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > eps ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p1 + d1 * s) - (p2 + d2 * t)).squaredNorm();
}

}  // namespace

OrientedBox orientedBox(const Eigen::AlignedBox3d& box_object,
                        const Eigen::Isometry3d& T_world_object) {
  OrientedBox b;
  b.T_world_box = T_world_object * Eigen::Translation3d(box_object.center());
  b.half_extents = box_object.sizes() / 2.0;
  return b;
}

std::array<Eigen::Vector3d, 8> corners(const OrientedBox& b) {
  std::array<Eigen::Vector3d, 8> out;
  for (int k = 0; k < 8; ++k) {
    Eigen::Vector3d c;
    for (int i = 0; i < 3; ++i) c[i] = (k >> i & 1) ? b.half_extents[i] : -b.half_extents[i];
    out[k] = b.T_world_box * c;
  }
  return out;
}

OrientedBox enclosingBox(const OrientedBox& b, const Eigen::Matrix3d& R_world_frame) {
  OrientedBox out;
  out.T_world_box.linear() = R_world_frame;
  out.T_world_box.translation() = b.T_world_box.translation();
  const Eigen::Matrix3d R_frame_box = R_world_frame.transpose() * b.T_world_box.linear();
  out.half_extents = R_frame_box.cwiseAbs() * b.half_extents;
  return out;
}

bool contains(const OrientedBox& outer, const OrientedBox& inner) {
  return contains(outer, inner, 0.0);
}

bool contains(const OrientedBox& outer, const OrientedBox& inner, double tolerance) {
  const Eigen::Isometry3d T_outer_world = outer.T_world_box.inverse();
  const Eigen::Vector3d limit = outer.half_extents.array() + tolerance + 1e-9;
  for (const Eigen::Vector3d& c : corners(inner))
    if (((T_outer_world * c).cwiseAbs() - limit).maxCoeff() > 0.0) return false;
  return true;
}

bool intersects(const OrientedBox& a, const OrientedBox& b) {
  const Eigen::Matrix3d A = a.T_world_box.linear(), B = b.T_world_box.linear();
  const Eigen::Matrix3d R = A.transpose() * B;  // b's axes in a's frame
  const Eigen::Matrix3d absR =
      R.cwiseAbs().array() + 1e-12;  // parallel edges: no false separations
  const Eigen::Vector3d t =
      A.transpose() * (b.T_world_box.translation() - a.T_world_box.translation());
  const Eigen::Vector3d& ha = a.half_extents;
  const Eigen::Vector3d& hb = b.half_extents;
  for (int i = 0; i < 3; ++i)  // a's face normals
    if (std::abs(t[i]) > ha[i] + absR.row(i).dot(hb)) return false;
  for (int j = 0; j < 3; ++j)  // b's face normals
    if (std::abs(t.dot(R.col(j))) > absR.col(j).dot(ha) + hb[j]) return false;
  for (int i = 0; i < 3; ++i)  // edge x edge: axis a_i x b_j
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = ha[i1] * absR(i2, j) + ha[i2] * absR(i1, j);
      const double rb = hb[j1] * absR(i, j2) + hb[j2] * absR(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) > ra + rb) return false;
    }
  return true;
}

double distance(const OrientedBox& a, const OrientedBox& b) {
  if (intersects(a, b)) return 0.0;
  const auto ca = corners(a), cb = corners(b);
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : ca) best = std::min(best, pointDistance(b, c));
  for (const Eigen::Vector3d& c : cb) best = std::min(best, pointDistance(a, c));
  double best2 = best * best;
  // Edges join corners that differ in one bit.
  for (int i = 0; i < 8; ++i)
    for (int bi = 0; bi < 3; ++bi) {
      if (i >> bi & 1) continue;
      for (int j = 0; j < 8; ++j)
        for (int bj = 0; bj < 3; ++bj) {
          if (j >> bj & 1) continue;
          best2 = std::min(best2, segmentDistance2(ca[i], ca[i | 1 << bi], cb[j], cb[j | 1 << bj]));
        }
    }
  return std::sqrt(best2);
}

}  // namespace sgt::relations
