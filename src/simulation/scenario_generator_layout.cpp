#include "scenario_generator_layout.hpp"

#include <algorithm>
#include <cmath>

namespace sgt::sim::gen {
namespace {

Eigen::Matrix2d rotation(double yaw) { return Eigen::Rotation2Dd(yaw).toRotationMatrix(); }

// Half the extent of footprint f along unit axis a.
double projectedHalf(const Footprint& f, const Eigen::Vector2d& a) {
  const Eigen::Matrix2d R = rotation(f.yaw);
  return f.half.x() * std::abs(a.dot(R.col(0))) + f.half.y() * std::abs(a.dot(R.col(1)));
}

}  // namespace

bool overlaps(const Footprint& a, const Footprint& b, double margin) {
  const Eigen::Matrix2d Ra = rotation(a.yaw), Rb = rotation(b.yaw);
  const Eigen::Vector2d d = b.centre - a.centre;
  for (const Eigen::Vector2d axis : {Ra.col(0), Ra.col(1), Rb.col(0), Rb.col(1)}) {
    const double gap = std::abs(d.dot(axis)) - projectedHalf(a, axis) - projectedHalf(b, axis);
    if (gap >= margin) return false;  // a separating axis
  }
  return true;
}

bool insideUsableArea(const Footprint& f) {
  const double hx = projectedHalf(f, Eigen::Vector2d::UnitX());
  const double hy = projectedHalf(f, Eigen::Vector2d::UnitY());
  return std::abs(f.centre.x()) + hx <= kUsableHalfX && std::abs(f.centre.y()) + hy <= kUsableHalfY;
}

GeneratedKey poseAt(const std::vector<GeneratedKey>& keys, double t) {
  if (t <= keys.front().t) return keys.front();
  if (t >= keys.back().t) return keys.back();
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const GeneratedKey& k) { return v < k.t; });
  const GeneratedKey &b = *next, &a = *(next - 1);
  const double s = (t - a.t) / (b.t - a.t);
  GeneratedKey k;
  k.t = t;
  k.xyz = a.xyz + s * (b.xyz - a.xyz);
  k.yaw_deg = a.yaw_deg + s * (b.yaw_deg - a.yaw_deg);
  return k;
}

double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

int uniformInt(std::mt19937& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}

bool chance(std::mt19937& rng, double p) { return uniform(rng, 0.0, 1.0) < p; }

}  // namespace sgt::sim::gen
