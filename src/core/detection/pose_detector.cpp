#include "scene_graph_tracker/detection/pose_detector.hpp"

namespace sgt::detection {

PoseDetector::PoseDetector(const std::string& model_yaml, const ObjectCatalog& catalog,
                           DecodeOptions decode, PnpOptions pnp, const InferenceOptions& inference)
    : detector_(model_yaml, decode, inference), pnp_(pnp) {
  if (detector_.info().keypoint_order != "dope_cuboid" ||
      detector_.info().keypoints != kCuboidKeypoints)
    throw DetectorError("model " + model_yaml + ": PnP needs " + std::to_string(kCuboidKeypoints) +
                        " keypoints in dope_cuboid order, the model has " +
                        std::to_string(detector_.info().keypoints) + " in '" +
                        detector_.info().keypoint_order + "'");
  for (const std::string& name : detector_.info().names) {
    if (!catalog.contains(name)) continue;
    const Eigen::AlignedBox3f& b = catalog.get(name).box;
    boxes_[name] = Eigen::AlignedBox3d(b.min().cast<double>(), b.max().cast<double>());
    cuboids_[name] = cuboidKeypoints(boxes_[name]);
  }
  if (cuboids_.empty())
    throw DetectorError("model " + model_yaml + ": none of its classes is in the object catalog");
}

std::vector<ObjectDetection> PoseDetector::detect(const cv::Mat& rgb, const PinholeModel& camera,
                                                  const RangeMeasurements* depth) {
  std::vector<ObjectDetection> out;
  for (Detection& d : detector_.detect(rgb)) {
    ++stats_.detections;
    ObjectDetection od;
    const auto cuboid = cuboids_.find(d.class_name);
    if (cuboid == cuboids_.end()) {
      ++stats_.rejected["class not in catalog"];
    } else {
      od.pnp = solveCuboidPnp(d.keypoints, cuboid->second, camera, pnp_);
      if (!od.pnp.ok()) ++stats_.rejected[pnpStatusName(od.pnp.status)];
      if (od.pnp.ok() && depth)
        if (const auto T =
                depthCorrectedPose(d, od.pnp.T_camera_object, boxes_.at(d.class_name), *depth))
          od.pnp.T_camera_object = *T;
    }
    od.detection = std::move(d);
    out.push_back(std::move(od));
  }
  return out;
}

}  // namespace sgt::detection
