// How much of an image shows what an earlier image did not: what a camera turning brought into
// view, what a person or a board that moved away uncovered, what came closer. The two images'
// small grey thumbnails are registered by phase correlation (cv::phaseCorrelate, the camera's
// pan and tilt); the new share is that of the thumbnail's pixels outside the shifted earlier one
// or changed beyond a grey-level margin.
#pragma once

#include <opencv2/core.hpp>

namespace sgt::detection {

class ViewNovelty {
 public:
  // The share of `rgb` (any size, 3 channels) new since the image remembered last; 1 before the
  // first.
  double share(const cv::Mat& rgb) const;
  void remember(const cv::Mat& rgb);

 private:
  cv::Mat thumbnail(const cv::Mat& rgb) const;

  cv::Mat last_;    // CV_32F thumbnail of the image remembered
  cv::Mat window_;  // Hanning window of the thumbnail's size
};

}  // namespace sgt::detection
