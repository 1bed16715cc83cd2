// Overlay images of an evaluation: each frame's colour image with the outlines of the tracked
// meshes (one colour per object, its label and depth residual beside it) and, thin and white,
// the outlines at the given (ground-truth) poses. Written as DIR/NNNNNN.jpg, and a contact sheet
// of evenly spaced frames: a person sees at a glance whether the fit is right.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace sgt {

struct OverlayObject {
  std::string label;  // e.g. "dragon_1 2.1 mm"
  int owner = -1;     // its index in the owner image
};

class OverlayWriter {
 public:
  explicit OverlayWriter(std::string dir);
  // `rgb`: 8-bit RGB. `tracked_owner` / `given_owner`: per pixel the index of the first surface
  // (-1: none), as SurfaceFitter::fit returns them; either may be empty.
  void add(const cv::Mat& rgb, const std::vector<int>& tracked_owner,
           const std::vector<OverlayObject>& tracked, const std::vector<int>& given_owner,
           std::size_t given_count);
  // Writes `path` (JPEG): up to `tiles` evenly spaced frames, 4 per row, at half size.
  void writeSheet(const std::string& path, std::size_t tiles = 12) const;
  std::size_t frames() const { return thumbnails_.size(); }

 private:
  std::string dir_;
  std::vector<cv::Mat> thumbnails_;  // BGR, half size, with the frame number
};

}  // namespace sgt
