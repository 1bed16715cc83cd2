// How far a measured range may lie from a predicted surface and still measure it: a fixed
// threshold, widened to a number of the sensor's noise sigmas where the noise is larger.
//
// The noise of a depth image grows with the square of the range (structured light and stereo:
// sigma = depth_sigma_at_1m * r^2); a LiDAR's is a constant range_sigma. A fixed threshold that
// suits a near object rejects most of the correct returns of one at 2.5 m, and a fit then looks
// like a false hypothesis.
#pragma once

#include <algorithm>

#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

struct RangeNoise {
  float depth_sigma_at_1m = 0.0015f;  // depth images: sigma = this * r^2 (m)
  float range_sigma = 0.01f;          // every other sensor: a constant sigma (m)

  // The sigma of a measurement of `m` at range r (m).
  float sigma(const RangeMeasurements& m, float r) const {
    return m.isDepthImage() ? depth_sigma_at_1m * r * r : range_sigma;
  }
};

// max(floor, per_m2 * r^2) for a measurement at range r.
struct RangeTolerance {
  float floor = 0.0f;
  float per_m2 = 0.0f;

  RangeTolerance() = default;
  RangeTolerance(float fixed) : floor(fixed) {}  // NOLINT: a fixed threshold converts implicitly
  RangeTolerance(float floor_m, float per_m2_m) : floor(floor_m), per_m2(per_m2_m) {}
  // `floor`, or `sigmas` noise sigmas of the sensor of `m` where that is larger (sigmas 0: floor).
  RangeTolerance(const RangeMeasurements& m, float floor_m, const RangeNoise& noise, float sigmas)
      : floor(floor_m) {
    if (!(sigmas > 0.0f)) return;
    if (m.isDepthImage())
      per_m2 = sigmas * noise.depth_sigma_at_1m;
    else
      floor = std::max(floor, sigmas * noise.range_sigma);
  }
  float at(float r) const { return std::max(floor, per_m2 * r * r); }
};

}  // namespace sgt
