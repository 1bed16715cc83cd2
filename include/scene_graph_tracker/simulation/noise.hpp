// Sensor noise for simulated measurements.
#pragma once

#include <cstdint>

#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

// Structured-light depth noise: sigma(z) = sigma_at_1m * z^2 along the optical axis (z in m),
// applied along each ray. Rays without a return stay without one.
void addDepthNoise(RangeMeasurements& m, double sigma_at_1m, std::uint32_t seed);
// LiDAR range noise: constant sigma along the ray.
void addRangeNoise(RangeMeasurements& m, double sigma, std::uint32_t seed);

}  // namespace sgt
