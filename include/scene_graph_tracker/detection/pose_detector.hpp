// From pixels to pose hypotheses: the keypoint detector, then cuboid PnP per detection against
// the class's box from the object catalog (the mesh's bounding box in the object frame).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scene_graph_tracker/detection/cuboid_pnp.hpp"
#include "scene_graph_tracker/detection/depth_translation.hpp"
#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"

namespace sgt::detection {

struct ObjectDetection {
  Detection detection;
  PnpResult pnp;  // T_camera_object when pnp.ok()
};

struct PoseDetectorStats {
  std::size_t detections = 0;
  std::map<std::string, std::size_t> rejected;  // by reason: PnP status or "class not in catalog"
};

class PoseDetector {
 public:
  // Throws DetectorError when the model cannot be loaded or none of its classes is in the catalog.
  PoseDetector(const std::string& model_yaml, const ObjectCatalog& catalog,
               DecodeOptions decode = {}, PnpOptions pnp = {},
               const InferenceOptions& inference = {});

  KeypointDetector& keypoints() { return detector_; }
  PnpOptions& pnpOptions() { return pnp_; }
  // Every detection with its PnP result (also the rejected ones, e.g. for a debug image). With a
  // registered depth image (range measurements of the same camera) the accepted poses get their
  // distance from it (depth_translation.hpp).
  std::vector<ObjectDetection> detect(const cv::Mat& rgb, const PinholeModel& camera,
                                      const RangeMeasurements* depth = nullptr);
  const PoseDetectorStats& stats() const { return stats_; }

 private:
  KeypointDetector detector_;
  PnpOptions pnp_;
  std::map<std::string, std::array<Eigen::Vector3d, kCuboidKeypoints>> cuboids_;  // per known class
  std::map<std::string, Eigen::AlignedBox3d> boxes_;
  PoseDetectorStats stats_;
};

}  // namespace sgt::detection
