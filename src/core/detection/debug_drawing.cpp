#include "scene_graph_tracker/detection/debug_drawing.hpp"

#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace sgt::detection {

namespace {

cv::Scalar classColour(int class_id) {
  static const cv::Scalar palette[] = {{230, 25, 75},  {60, 180, 75},  {255, 225, 25},
                                       {0, 130, 200},  {245, 130, 48}, {145, 30, 180},
                                       {70, 240, 240}, {240, 50, 230}};
  return palette[(class_id < 0 ? 0 : class_id) % 8];
}

cv::Point pt(const Eigen::Vector2d& p) {
  return cv::Point(static_cast<int>(p.x()), static_cast<int>(p.y()));
}

}  // namespace

void drawDetections(cv::Mat& rgb, const std::vector<ObjectDetection>& detections,
                    float min_visibility) {
  // Cuboid edges between DOPE keypoints: front face, rear face, the four connecting edges.
  static const int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                    {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const ObjectDetection& od : detections) {
    const Detection& d = od.detection;
    const cv::Scalar c = classColour(d.class_id);
    cv::rectangle(rgb, pt(d.box_min), pt(d.box_max), c, 1);
    if (d.keypoints.size() >= static_cast<std::size_t>(kCuboidKeypoints)) {
      for (int e = 0; e < 12; ++e)
        cv::line(rgb, pt(d.keypoints[kEdges[e][0]].px), pt(d.keypoints[kEdges[e][1]].px), c,
                 e < 4 ? 2 : 1, cv::LINE_AA);
    }
    for (const Keypoint& k : d.keypoints)
      cv::circle(rgb, pt(k.px), 3, c, k.visibility >= min_visibility ? cv::FILLED : 1, cv::LINE_AA);
    char label[96];
    std::snprintf(label, sizeof label, "%s %.2f%s%s", d.class_name.c_str(), d.score,
                  od.pnp.ok() ? "" : " ", od.pnp.ok() ? "" : pnpStatusName(od.pnp.status));
    cv::putText(rgb, label, pt(d.box_min) + cv::Point(0, -4), cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1,
                cv::LINE_AA);
  }
}

}  // namespace sgt::detection
