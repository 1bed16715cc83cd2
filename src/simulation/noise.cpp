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

}  // namespace sgt
