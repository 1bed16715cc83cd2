// Keypoint detector: a YOLOv8-pose style ONNX model run through OpenCV DNN on the CPU.
//
// Pipeline: letterbox the RGB image into the network input (aspect kept, grey padding), one
// forward pass, decode the ultralytics output layout (1, 4 + nc + K*3, N) — per anchor the box
// centre x, centre y, w, h in input pixels, nc class scores (already sigmoided, no objectness),
// then K keypoints as (x, y, visibility) — keep anchors above the score threshold, class-aware
// NMS, map boxes and keypoints back to image pixels.
//
// The model's metadata lives in a small YAML beside the .onnx (see loadModelInfo). A model whose
// output does not fit its metadata is refused with an error that names the numbers.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgt::detection {

class DetectorError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ModelInfo {
  std::string onnx_path;  // resolved
  int input_width = 320;
  int input_height = 320;
  std::vector<std::string> names;  // class names in output order
  int keypoints = 9;
  std::string keypoint_order = "dope_cuboid";
  int letterbox_pad = 114;     // grey value of the padding
  double scale = 1.0 / 255.0;  // pixel value -> network input
  bool swap_rb = false;        // false: the network takes RGB
  // Per-class minimum scores (optional `score_thresholds: {klt: 0.5, ...}`): a model's scores are
  // not calibrated alike across classes; evaluate_detector suggests these from held-out frames.
  // A class's detections need max(DecodeOptions::score_threshold, its entry).
  std::map<std::string, float> score_thresholds;

  int channels() const { return 4 + static_cast<int>(names.size()) + 3 * keypoints; }
};

// Metadata YAML:
//   model: sgt_keypoints.onnx        # optional; default: the YAML's name with .onnx
//   input_width: 320
//   input_height: 320
//   names: [multimeter, screwdriver, materialbox, klt, relay]
//   keypoints: 9
//   keypoint_order: dope_cuboid      # the only order PnP understands today
//   letterbox_pad: 114               # optional
//   scale: 0.00392156862745098       # optional (1/255)
//   swap_rb: false                   # optional; true when the network takes BGR
ModelInfo loadModelInfo(const std::string& yaml_uri);  // a path or package:// URI

// Where the image lands in the network input: input = image * scale + pad, both in continuous
// coordinates (pixel (0, 0) covers [0, 1) x [0, 1), the convention of ultralytics' labels).
struct Letterbox {
  double scale = 1.0;
  double pad_x = 0.0, pad_y = 0.0;
  int input_width = 0, input_height = 0;

  Eigen::Vector2d toInput(const Eigen::Vector2d& image_px) const {
    return image_px * scale + Eigen::Vector2d(pad_x, pad_y);
  }
  Eigen::Vector2d toImage(const Eigen::Vector2d& input_px) const {
    return (input_px - Eigen::Vector2d(pad_x, pad_y)) / scale;
  }
};

Letterbox letterboxGeometry(int image_width, int image_height, int input_width, int input_height);
// The letterboxed image (input_height x input_width, same type as `image`).
cv::Mat letterbox(const cv::Mat& image, const Letterbox& lb, int pad_value);

struct Keypoint {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();  // image pixels, centre of pixel (0, 0) at (0, 0)
                                                 // as in camera_info's K
  float visibility = 0.0f;                       // 0..1
};

struct Detection {
  int class_id = -1;
  std::string class_name;
  float score = 0.0f;
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero(),
                  box_max = Eigen::Vector2d::Zero();  // image px, as keypoints
  std::vector<Keypoint> keypoints;
};

struct DecodeOptions {
  float score_threshold = 0.35f;
  float nms_iou = 0.5f;
  int max_detections = 100;
};

// Where OpenCV DNN runs the network: backend opencv | cuda | default, target cpu | opencl |
// opencl_fp16 | cuda | cuda_fp16. A pair this OpenCV build cannot run (no CUDA, no OpenCL
// device) falls back to opencv / cpu, and KeypointDetector::inferenceNote() says so.
struct InferenceOptions {
  std::string backend = "opencv";
  std::string target = "cpu";
};

// Decodes a raw output blob (dims 1 x C x N, float). Throws DetectorError when C does not match
// the metadata.
std::vector<Detection> decodeYoloPose(const cv::Mat& output, const ModelInfo& info,
                                      const Letterbox& lb, const DecodeOptions& options);

double iou(const Detection& a, const Detection& b);
// Class-aware non-maximum suppression: keeps the best-scoring detection of overlapping ones of
// the same class; the result is sorted by score.
std::vector<Detection> nonMaximumSuppression(std::vector<Detection> detections, float iou_threshold,
                                             int max_detections);

class KeypointDetector {
 public:
  // Loads the metadata and the network; checks the output layout with one forward pass.
  // Throws DetectorError for an unknown backend or target name.
  explicit KeypointDetector(const std::string& metadata_yaml, DecodeOptions options = {},
                            const InferenceOptions& inference = {});
  ~KeypointDetector();
  KeypointDetector(const KeypointDetector&) = delete;
  KeypointDetector& operator=(const KeypointDetector&) = delete;

  const ModelInfo& info() const { return info_; }
  // Ignore the metadata's per-class score_thresholds (evaluate_detector calibrates them).
  void clearScoreThresholds() { info_.score_thresholds.clear(); }
  DecodeOptions& options() { return options_; }
  // Why the requested backend / target is not used; empty when it is.
  const std::string& inferenceNote() const { return inference_note_; }
  // `rgb`: 8-bit, 3 channels, RGB order.
  std::vector<Detection> detect(const cv::Mat& rgb);

 private:
  cv::Mat forward(const cv::Mat& rgb, const Letterbox& lb);
  struct Net;
  ModelInfo info_;
  DecodeOptions options_;
  std::string inference_note_;
  std::unique_ptr<Net> net_;
};

}  // namespace sgt::detection
