#include "scene_graph_tracker/simulation/noise.hpp"

#include <random>

namespace sgt {

void addDepthNoise(RangeMeasurements& m, double sigma_at_1m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < m.range.size(); ++i) {
    if (!m.valid(i)) continue;
    const double dz = m.rays->directions[i].z();
    const double z = m.range[i] * dz;
    const double noisy_z = z + gauss(rng) * sigma_at_1m * z * z;
    m.range[i] = static_cast<float>(noisy_z / dz);
  }
}

void addRangeNoise(RangeMeasurements& m, double sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, sigma);
  for (std::size_t i = 0; i < m.range.size(); ++i)
    if (m.valid(i)) m.range[i] += static_cast<float>(gauss(rng));
}

Eigen::Isometry3d disturbPose(const Eigen::Isometry3d& T, double sigma_t, double sigma_r,
                              std::mt19937& rng, std::normal_distribution<double>& gauss) {
  Eigen::Isometry3d out = T;
  out.translation() += sigma_t * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  const Eigen::Vector3d w = sigma_r * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  if (w.norm() > 0.0)
    out.linear() = out.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  return out;
}

}  // namespace sgt
