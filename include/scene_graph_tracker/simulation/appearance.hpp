// Appearance randomisation for rendered training images (render_dataset): procedural surface
// patterns in place of flat colours, and what a real camera does to an image (exposure, white
// balance, gamma, blur, sensor noise, JPEG). A detector trained on flat-shaded renders learns
// colours; one trained under these learns shapes and outlines, which carry over to real images of
// objects whose real colours and textures the meshes do not hold.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

namespace sgt::sim {

// A pattern mixing a surface's albedo with a second colour, evaluated at world points (a rendered
// image is one instant, so world and object coordinates are equivalent for it).
struct SurfacePattern {
  enum class Kind { kChecker, kStripes, kNoise, kBlotches };
  Kind kind = Kind::kChecker;
  Eigen::Vector3f second = Eigen::Vector3f::Zero();      // the other colour, RGB 0..1
  float scale = 0.02f;                                   // cell, stripe period or noise size (m)
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();  // stripes run across it (unit)
  std::uint32_t seed = 0;                                // noise lattice
};

// Weight in [0, 1] of the second colour at a world point.
float patternWeight(const SurfacePattern& pattern, const Eigen::Vector3f& p_world);

struct CameraEffects {
  float gain = 1.0f;                                        // exposure
  Eigen::Vector3f white_balance = Eigen::Vector3f::Ones();  // per channel, RGB
  float gamma = 1.0f;                                       // out = in^(1/gamma)
  float blur_sigma = 0.0f;                                  // Gaussian blur, pixels (0: none)
  float noise_sigma = 0.0f;                                 // Gaussian sensor noise, 8-bit levels
  int jpeg_quality = 0;                                     // re-encoded at this quality (0: not)
  std::uint32_t seed = 0;                                   // noise
};

// Applies `effects` to an 8-bit 3-channel BGR image in place.
void applyCameraEffects(cv::Mat& bgr, const CameraEffects& effects);

}  // namespace sgt::sim
