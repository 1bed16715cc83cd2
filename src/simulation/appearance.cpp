#include "scene_graph_tracker/simulation/appearance.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

namespace sgt::sim {
namespace {

// A value in [0, 1) per integer lattice point.
float latticeValue(long x, long y, long z, std::uint32_t seed) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B185EBCA87ull ^
                    static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull ^
                    static_cast<std::uint64_t>(seed) * 0x27D4EB2F165667C5ull;
  // MurmurHash3's finaliser: every input bit reaches every output bit.
  h ^= h >> 33, h *= 0xff51afd7ed558ccdull, h ^= h >> 33, h *= 0xc4ceb9fe1a85ec53ull, h ^= h >> 33;
  return static_cast<float>(h >> 40) / static_cast<float>(1ull << 24);
}

float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

// Trilinear value noise in [0, 1) with smoothstep weights.
float valueNoise(const Eigen::Vector3f& p, std::uint32_t seed) {
  const Eigen::Vector3f f = p.array().floor();
  const long x = static_cast<long>(f.x()), y = static_cast<long>(f.y()),
             z = static_cast<long>(f.z());
  const float u = smooth(p.x() - f.x()), v = smooth(p.y() - f.y()), w = smooth(p.z() - f.z());
  float sum = 0.0f;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    sum += (dx ? u : 1 - u) * (dy ? v : 1 - v) * (dz ? w : 1 - w) *
           latticeValue(x + dx, y + dy, z + dz, seed);
  }
  return sum;
}

}  // namespace

float patternWeight(const SurfacePattern& s, const Eigen::Vector3f& p_world) {
  const Eigen::Vector3f q = p_world / std::max(s.scale, 1e-4f);
  switch (s.kind) {
    case SurfacePattern::Kind::kChecker: {
      const long sum = static_cast<long>(std::floor(q.x())) + static_cast<long>(std::floor(q.y())) +
                       static_cast<long>(std::floor(q.z()));
      return (sum & 1) ? 1.0f : 0.0f;
    }
    case SurfacePattern::Kind::kStripes:
      return 0.5f + 0.5f * std::sin(2.0f * static_cast<float>(M_PI) * s.direction.dot(q));
    case SurfacePattern::Kind::kNoise:
      return 0.65f * valueNoise(q, s.seed) + 0.35f * valueNoise(2.7f * q, s.seed + 1);
    case SurfacePattern::Kind::kBlotches:
      return valueNoise(q, s.seed) > 0.5f ? 1.0f : 0.0f;
  }
  return 0.0f;
}

void applyCameraEffects(cv::Mat& bgr, const CameraEffects& e) {
  cv::Mat f;
  bgr.convertTo(f, CV_32FC3, 1.0 / 255.0);
  const cv::Scalar balance(e.gain * e.white_balance.z(), e.gain * e.white_balance.y(),
                           e.gain * e.white_balance.x());
  cv::multiply(f, balance, f);
  cv::max(f, 0.0, f);
  if (e.gamma != 1.0f) cv::pow(f, 1.0 / e.gamma, f);
  if (e.blur_sigma > 0.0f) cv::GaussianBlur(f, f, cv::Size(0, 0), e.blur_sigma);
  if (e.noise_sigma > 0.0f) {
    cv::Mat noise(f.size(), f.type());
    cv::RNG rng(e.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, e.noise_sigma / 255.0);
    f += noise;
  }
  f.convertTo(bgr, CV_8UC3, 255.0);  // saturates to 0..255
  if (e.jpeg_quality > 0) {
    std::vector<std::uint8_t> jpeg;
    cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, e.jpeg_quality});
    bgr = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  }
}

}  // namespace sgt::sim
