#include "scene_graph_tracker/detection/view_novelty.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace sgt::detection {
namespace {
constexpr int kWidth = 80, kHeight = 60;  // thumbnail: enough for shifts of a few pixels
// A thumbnail pixel whose grey level (mean-free, 0..255) differs by more than this from the
// remembered one shows something else: what was behind a person who left, an object come closer.
constexpr float kChanged = 16.0f;

// The share of a's pixels that b, a shifted by `shift`, shows unchanged.
double unchangedShare(const cv::Mat& a, const cv::Mat& b, const cv::Point2d& shift) {
  const int dx = static_cast<int>(std::lround(shift.x)),
            dy = static_cast<int>(std::lround(shift.y));
  const int w = a.cols - std::abs(dx), h = a.rows - std::abs(dy);
  if (w <= 0 || h <= 0) return 0.0;
  const cv::Mat pa = a(cv::Rect(std::max(0, -dx), std::max(0, -dy), w, h));  // b(x) = a(x - shift)
  const cv::Mat pb = b(cv::Rect(std::max(0, dx), std::max(0, dy), w, h));
  cv::Mat diff;  // with each side's mean over the overlap taken out (exposure changes)
  cv::absdiff(pa - cv::mean(pa)[0], pb - cv::mean(pb)[0], diff);
  return static_cast<double>(cv::countNonZero(diff <= kChanged)) / a.total();
}
}  // namespace

cv::Mat ViewNovelty::thumbnail(const cv::Mat& rgb) const {
  cv::Mat grey, small, out;
  cv::cvtColor(rgb, grey, rgb.channels() == 4 ? cv::COLOR_RGBA2GRAY : cv::COLOR_RGB2GRAY);
  cv::resize(grey, small, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_AREA);
  small.convertTo(out, CV_32F);
  return out;
}

double ViewNovelty::share(const cv::Mat& rgb) const {
  if (last_.empty() || rgb.empty()) return 1.0;
  const cv::Mat now = thumbnail(rgb);
  // Mean-free, so that the window's shape common to both does not correlate.
  const cv::Point2d shift =
      cv::phaseCorrelate(last_ - cv::mean(last_)[0], now - cv::mean(now)[0], window_);
  return 1.0 - unchangedShare(last_, now, shift);
}

void ViewNovelty::remember(const cv::Mat& rgb) {
  if (rgb.empty()) return;
  last_ = thumbnail(rgb);
  if (window_.empty()) cv::createHanningWindow(window_, last_.size(), CV_32F);
}

}  // namespace sgt::detection
