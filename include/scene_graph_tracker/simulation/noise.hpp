// Sensor noise for simulated measurements.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <random>

#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

// Structured-light depth noise: sigma(z) = sigma_at_1m * z^2 along the optical axis (z in m),
// applied along each ray. Rays without a return stay without one.
void addDepthNoise(RangeMeasurements& m, double sigma_at_1m, std::uint32_t seed);
// LiDAR range noise: constant sigma along the ray.
void addRangeNoise(RangeMeasurements& m, double sigma, std::uint32_t seed);
// The simulated detector's pose error: T moved by sigma_t (m) per axis of its parent frame, then
// turned by a rotation vector of sigma_r (rad) per axis in its own frame. Draws six variates from
// `gauss` (mean 0, sigma 1) in that order.
Eigen::Isometry3d disturbPose(const Eigen::Isometry3d& T, double sigma_t, double sigma_r,
                              std::mt19937& rng, std::normal_distribution<double>& gauss);

}  // namespace sgt
