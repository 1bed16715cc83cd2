// The range along the viewing ray is what PnP on a few noisy keypoints gets worst (a 2 px error
// of an object 10 cm wide at 1 m moves it ~2 cm in depth, and a small model's keypoints are off
// by tens of pixels). With a registered depth image the distance can be measured instead: the
// object's centre goes onto the ray through the detection box's centre, at the median measured
// range of the box's central half plus the distance from the object's centre to where that ray
// enters its box (turned by the PnP rotation). The rotation is kept.
#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt::detection {

struct DepthTranslationOptions {
  double box_fraction = 0.5;  // of the detection box (centred) whose depth pixels are used
  int min_pixels = 20;        // valid depth pixels needed there
};

// `depth`: a depth image as range measurements of a pinhole camera registered with the image the
// detection comes from (same size and intrinsics). nullopt when it is not a pinhole set of that
// size or too few pixels in the box have a return. `box` is the class's box in the object frame.
std::optional<Eigen::Isometry3d> depthCorrectedPose(const Detection& detection,
                                                    const Eigen::Isometry3d& T_camera_object,
                                                    const Eigen::AlignedBox3d& box,
                                                    const RangeMeasurements& depth,
                                                    const DepthTranslationOptions& options = {});

}  // namespace sgt::detection
