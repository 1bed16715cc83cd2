#include "scene_graph_tracker/simulation/photo_appearance.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace sgt::sim {
namespace {

bool isPhotoFile(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png";
}

// Index into [0, n) of a coordinate that repeats mirrored: 0 1 .. n-1 n-1 .. 1 0 0 1 ..
int mirroredIndex(float x, int n) {
  const long period = 2L * n;
  long i = static_cast<long>(std::floor(x)) % period;
  if (i < 0) i += period;
  return static_cast<int>(i < n ? i : period - 1 - i);
}

}  // namespace

std::vector<std::shared_ptr<const cv::Mat>> loadPhotos(const std::filesystem::path& dir,
                                                       int max_side) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file() && isPhotoFile(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<std::shared_ptr<const cv::Mat>> photos;
  for (const auto& f : files) {
    cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
    if (img.empty()) {
      std::cerr << "photos: cannot read " << f << ", skipped\n";
      continue;
    }
    const int side = std::max(img.cols, img.rows);
    if (side > max_side) {
      const double s = static_cast<double>(max_side) / side;
      cv::resize(img, img, cv::Size(), s, s, cv::INTER_AREA);
    }
    photos.push_back(std::make_shared<const cv::Mat>(std::move(img)));
  }
  return photos;
}

Eigen::Vector3f photoColour(const PhotoTexture& t, const Eigen::Vector3f& p,
                            const Eigen::Vector3f& n) {
  const cv::Mat& img = *t.image;
  int axis = 0;
  n.cwiseAbs().maxCoeff(&axis);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const float px_per_m =
      static_cast<float>(std::max(img.cols, img.rows)) / std::max(t.size_m, 1e-3f);
  const int u = mirroredIndex((p[a] + t.offset_m.x()) * px_per_m, img.cols);
  const int v = mirroredIndex((p[b] + t.offset_m.y()) * px_per_m, img.rows);
  const cv::Vec3b c = img.at<cv::Vec3b>(v, u);
  return Eigen::Vector3f(c[2], c[1], c[0]) / 255.0f;
}

cv::Mat photoView(const cv::Mat& photo, cv::Size size, double zoom, double u, double v,
                  bool mirror) {
  // The largest region of the view's aspect ratio that fits the photo, shrunk by the zoom.
  const double aspect = static_cast<double>(size.width) / size.height;
  double w = photo.cols, h = w / aspect;
  if (h > photo.rows) h = photo.rows, w = h * aspect;
  w /= std::max(zoom, 1.0), h /= std::max(zoom, 1.0);
  const double x0 = std::clamp(u, 0.0, 1.0) * (photo.cols - w);
  const double y0 = std::clamp(v, 0.0, 1.0) * (photo.rows - h);
  const cv::Rect roi(static_cast<int>(x0), static_cast<int>(y0), std::max(1, static_cast<int>(w)),
                     std::max(1, static_cast<int>(h)));
  cv::Mat view;
  cv::resize(photo(roi & cv::Rect(0, 0, photo.cols, photo.rows)), view, size, 0, 0,
             cv::INTER_LINEAR);
  if (mirror) cv::flip(view, view, 1);
  return view;
}

}  // namespace sgt::sim
