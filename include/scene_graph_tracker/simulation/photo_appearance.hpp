// Photographs in rendered training images (render_dataset --photos): real images as surface
// textures and as backgrounds behind the rendered scene. Procedural patterns teach a detector that
// colour is not the class; photographs add what real scenes have and patterns lack (natural
// statistics, clutter, text, pictures on the objects themselves, such as a picture cube's faces).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace sgt::sim {

// Every .jpg, .jpeg and .png under `dir` (sorted by path, so a seed draws the same photos on
// every machine), read as 8-bit BGR and shrunk to at most `max_side` pixels on the long side.
// Unreadable files are skipped with a warning on stderr; an empty result is the caller's error.
std::vector<std::shared_ptr<const cv::Mat>> loadPhotos(const std::filesystem::path& dir,
                                                       int max_side = 800);

// A photograph wrapped around a surface by box mapping: a world point is projected along the axis
// its normal points most along, the photo spans `size_m` metres and repeats (mirrored at its
// edges, so that no seam shows), shifted by `offset_m`.
struct PhotoTexture {
  std::shared_ptr<const cv::Mat> image;  // 8-bit BGR
  float size_m = 0.1f;
  Eigen::Vector2f offset_m = Eigen::Vector2f::Zero();
};

// RGB 0..1 of the texture at a world point with a world normal.
Eigen::Vector3f photoColour(const PhotoTexture& texture, const Eigen::Vector3f& p_world,
                            const Eigen::Vector3f& n_world);

// A `size` view of `photo`: zoomed by `zoom` (>= 1: the view shows 1 / zoom of the photo's
// shorter side scaled to fill it), its top-left corner at (`u`, `v`) in [0, 1] of the room left,
// mirrored left to right if `mirror`.
cv::Mat photoView(const cv::Mat& photo, cv::Size size, double zoom, double u, double v,
                  bool mirror);

}  // namespace sgt::sim
