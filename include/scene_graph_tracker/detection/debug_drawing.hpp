// Draws detections on an RGB image for a person to look at: the 2D box, the cuboid's edges
// through the keypoints (front face thicker), the keypoints (hollow when not visible), class and
// score, and the PnP status when it rejected the pose.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "scene_graph_tracker/detection/pose_detector.hpp"

namespace sgt::detection {

void drawDetections(cv::Mat& rgb, const std::vector<ObjectDetection>& detections,
                    float min_visibility = 0.5f);

}  // namespace sgt::detection
