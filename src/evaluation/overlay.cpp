#include "scene_graph_tracker/evaluation/overlay.hpp"

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/evaluation/surface_fit.hpp"

namespace sgt {
namespace {

const std::vector<cv::Scalar>& palette() {  // BGR
  static const std::vector<cv::Scalar> colours = {{0, 200, 0},   {255, 128, 0}, {0, 128, 255},
                                                  {255, 0, 255}, {0, 255, 255}, {128, 0, 255}};
  return colours;
}

// The label of object k at the top of its pixels.
void label(cv::Mat& bgr, const std::vector<int>& owner, const OverlayObject& o,
           const cv::Scalar& colour) {
  int top = bgr.rows, left = bgr.cols;
  for (std::size_t i = 0; i < owner.size(); ++i)
    if (owner[i] == o.owner) {
      const int v = static_cast<int>(i) / bgr.cols, u = static_cast<int>(i) % bgr.cols;
      if (v < top) top = v, left = u;
    }
  if (top == bgr.rows) return;
  const cv::Point at(std::max(0, left - 40), std::max(14, top - 6));
  cv::putText(bgr, o.label, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 3, cv::LINE_AA);
  cv::putText(bgr, o.label, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
}

}  // namespace

OverlayWriter::OverlayWriter(std::string dir) : dir_(std::move(dir)) {
  std::filesystem::create_directories(dir_);
}

void OverlayWriter::add(const cv::Mat& rgb, const std::vector<int>& tracked_owner,
                        const std::vector<OverlayObject>& tracked,
                        const std::vector<int>& given_owner, std::size_t given_count) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  drawOutlines(bgr, given_owner, given_count, {{255, 255, 255}}, 1);
  std::vector<cv::Scalar> colours;
  for (std::size_t k = 0; k < tracked.size(); ++k)
    colours.push_back(palette()[k % palette().size()]);
  drawOutlines(bgr, tracked_owner, tracked.size(), colours, 2);
  if (tracked_owner.size() == bgr.total())
    for (std::size_t k = 0; k < tracked.size(); ++k)
      label(bgr, tracked_owner, tracked[k], colours[k]);
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.jpg", thumbnails_.size());
  cv::imwrite(dir_ + "/" + name, bgr);
  cv::Mat half;
  cv::resize(bgr, half, {}, 0.5, 0.5, cv::INTER_AREA);
  cv::putText(half, std::to_string(thumbnails_.size()), {6, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.55,
              {255, 255, 255}, 2, cv::LINE_AA);
  thumbnails_.push_back(half);
}

void OverlayWriter::writeSheet(const std::string& path, std::size_t tiles) const {
  if (thumbnails_.empty() || tiles == 0) return;
  const std::size_t n = std::min(tiles, thumbnails_.size()), columns = std::min<std::size_t>(4, n);
  const std::size_t rows = (n + columns - 1) / columns;
  const cv::Size tile = thumbnails_.front().size();
  cv::Mat sheet(static_cast<int>(rows) * tile.height, static_cast<int>(columns) * tile.width,
                CV_8UC3, cv::Scalar(0, 0, 0));
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t frame = n == 1 ? 0 : k * (thumbnails_.size() - 1) / (n - 1);
    const cv::Mat& t = thumbnails_[frame];
    if (t.size() != tile) continue;
    t.copyTo(sheet(cv::Rect(static_cast<int>(k % columns) * tile.width,
                            static_cast<int>(k / columns) * tile.height, tile.width, tile.height)));
  }
  cv::imwrite(path, sheet);
}

}  // namespace sgt
