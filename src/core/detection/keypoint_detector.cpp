#include "scene_graph_tracker/detection/keypoint_detector.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/geometry/mesh_io.hpp"

namespace sgt::detection {

namespace fs = std::filesystem;

ModelInfo loadModelInfo(const std::string& yaml_uri) {
  std::string yaml_path = yaml_uri;
  YAML::Node y;
  try {
    yaml_path = resolveResourcePath(yaml_uri);
    y = YAML::LoadFile(yaml_path);
  } catch (const std::exception& e) {
    throw DetectorError("model metadata " + yaml_path + ": " + e.what());
  }
  const auto need = [&](const char* key) {
    if (!y[key]) throw DetectorError("model metadata " + yaml_path + ": missing '" + key + "'");
    return y[key];
  };
  ModelInfo info;
  try {
    const fs::path yaml(yaml_path);
    const fs::path onnx = y["model"] ? fs::path(y["model"].as<std::string>())
                                     : yaml.filename().replace_extension(".onnx");
    info.onnx_path = (onnx.is_absolute() ? onnx : yaml.parent_path() / onnx).string();
    info.input_width = need("input_width").as<int>();
    info.input_height = need("input_height").as<int>();
    info.names = need("names").as<std::vector<std::string>>();
    info.keypoints = need("keypoints").as<int>();
    if (y["keypoint_order"]) info.keypoint_order = y["keypoint_order"].as<std::string>();
    if (y["letterbox_pad"]) info.letterbox_pad = y["letterbox_pad"].as<int>();
    if (y["scale"]) info.scale = y["scale"].as<double>();
    if (y["swap_rb"]) info.swap_rb = y["swap_rb"].as<bool>();
    if (y["score_thresholds"])
      info.score_thresholds = y["score_thresholds"].as<std::map<std::string, float>>();
  } catch (const YAML::Exception& e) {
    throw DetectorError("model metadata " + yaml_path + ": " + e.what());
  }
  if (info.input_width <= 0 || info.input_height <= 0 || info.names.empty() || info.keypoints < 0)
    throw DetectorError("model metadata " + yaml_path +
                        ": input size, names and keypoints must be positive");
  for (const auto& [name, t] : info.score_thresholds)
    if (std::find(info.names.begin(), info.names.end(), name) == info.names.end())
      throw DetectorError("model metadata " + yaml_path + ": score_thresholds names '" + name +
                          "', not one of its classes");
  return info;
}

Letterbox letterboxGeometry(int image_width, int image_height, int input_width, int input_height) {
  if (image_width <= 0 || image_height <= 0) throw DetectorError("letterbox: empty image");
  Letterbox lb;
  lb.input_width = input_width;
  lb.input_height = input_height;
  lb.scale = std::min(static_cast<double>(input_width) / image_width,
                      static_cast<double>(input_height) / image_height);
  // Whole-pixel padding, the image centred (the odd pixel goes right / down).
  lb.pad_x = std::floor(0.5 * (input_width - std::round(image_width * lb.scale)));
  lb.pad_y = std::floor(0.5 * (input_height - std::round(image_height * lb.scale)));
  return lb;
}

cv::Mat letterbox(const cv::Mat& image, const Letterbox& lb, int pad_value) {
  const int w = static_cast<int>(std::round(image.cols * lb.scale));
  const int h = static_cast<int>(std::round(image.rows * lb.scale));
  cv::Mat resized;
  if (w == image.cols && h == image.rows) {
    resized = image;
  } else {
    cv::resize(image, resized, cv::Size(w, h), 0, 0,
               lb.scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  }
  cv::Mat out(lb.input_height, lb.input_width, image.type(), cv::Scalar::all(pad_value));
  resized.copyTo(out(cv::Rect(static_cast<int>(lb.pad_x), static_cast<int>(lb.pad_y), w, h)));
  return out;
}

double iou(const Detection& a, const Detection& b) {
  const Eigen::Vector2d lo = a.box_min.cwiseMax(b.box_min), hi = a.box_max.cwiseMin(b.box_max);
  const Eigen::Vector2d d = (hi - lo).cwiseMax(0.0);
  const double inter = d.x() * d.y();
  const auto area = [](const Detection& x) { return (x.box_max - x.box_min).cwiseMax(0.0).prod(); };
  const double uni = area(a) + area(b) - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

std::vector<Detection> nonMaximumSuppression(std::vector<Detection> detections, float iou_threshold,
                                             int max_detections) {
  std::stable_sort(detections.begin(), detections.end(),
                   [](const Detection& a, const Detection& b) { return a.score > b.score; });
  std::vector<Detection> kept;
  for (auto& d : detections) {
    if (static_cast<int>(kept.size()) >= max_detections) break;
    const bool suppressed = std::any_of(kept.begin(), kept.end(), [&](const Detection& k) {
      return k.class_id == d.class_id && iou(k, d) > iou_threshold;
    });
    if (!suppressed) kept.push_back(std::move(d));
  }
  return kept;
}

namespace {

// Network coordinates are continuous (pixel (0, 0) covers [0, 1) x [0, 1), as in ultralytics'
// labels); image pixels here are pixel-centre coordinates like camera_info's K (centre of pixel
// (0, 0) at 0, 0).
Eigen::Vector2d toPixel(const Letterbox& lb, const Eigen::Vector2d& input) {
  return lb.toImage(input) - Eigen::Vector2d(0.5, 0.5);
}

}  // namespace

std::vector<Detection> decodeYoloPose(const cv::Mat& output, const ModelInfo& info,
                                      const Letterbox& lb, const DecodeOptions& options) {
  if (output.dims != 3 || output.size[0] != 1 || output.type() != CV_32F) {
    std::string dims;
    for (int i = 0; i < output.dims; ++i) dims += (i ? " x " : "") + std::to_string(output.size[i]);
    throw DetectorError("model output must be a float tensor 1 x C x N (YOLOv8-pose layout), got " +
                        dims);
  }
  const int channels = output.size[1], anchors = output.size[2];
  const int nc = static_cast<int>(info.names.size());
  if (channels != info.channels())
    throw DetectorError("model output has " + std::to_string(channels) +
                        " channels per anchor, its metadata expects 4 + " + std::to_string(nc) +
                        " classes + " + std::to_string(info.keypoints) +
                        " keypoints x 3 = " + std::to_string(info.channels()));
  const float* data = output.ptr<float>();
  const auto at = [&](int c, int a) { return data[static_cast<std::size_t>(c) * anchors + a]; };
  std::vector<float> threshold(nc, options.score_threshold);
  for (int c = 0; c < nc; ++c)
    if (const auto it = info.score_thresholds.find(info.names[c]);
        it != info.score_thresholds.end())
      threshold[c] = std::max(threshold[c], it->second);
  std::vector<Detection> candidates;
  for (int a = 0; a < anchors; ++a) {
    int best = 0;
    for (int c = 1; c < nc; ++c)
      if (at(4 + c, a) > at(4 + best, a)) best = c;
    const float score = at(4 + best, a);
    if (!(score >= threshold[best])) continue;  // also drops NaN
    Detection d;
    d.class_id = best;
    d.class_name = info.names[best];
    d.score = score;
    const Eigen::Vector2d centre(at(0, a), at(1, a)), half(0.5 * at(2, a), 0.5 * at(3, a));
    d.box_min = toPixel(lb, centre - half);
    d.box_max = toPixel(lb, centre + half);
    d.keypoints.resize(info.keypoints);
    for (int k = 0; k < info.keypoints; ++k) {
      const int c = 4 + nc + 3 * k;
      d.keypoints[k].px = toPixel(lb, Eigen::Vector2d(at(c, a), at(c + 1, a)));
      d.keypoints[k].visibility = at(c + 2, a);
    }
    candidates.push_back(std::move(d));
  }
  return nonMaximumSuppression(std::move(candidates), options.nms_iou, options.max_detections);
}

struct KeypointDetector::Net {
  cv::dnn::Net net;
};

namespace {

template <class Enum>
Enum byName(const std::map<std::string, Enum>& names, const std::string& name, const char* what) {
  const auto it = names.find(name);
  if (it != names.end()) return it->second;
  std::string known;
  for (const auto& [n, e] : names) known += (known.empty() ? "" : ", ") + n;
  throw DetectorError(std::string("unknown DNN ") + what + " '" + name + "' (" + known + ")");
}

// Sets the backend and target; returns why they are not the requested ones (empty: they are).
std::string setInference(cv::dnn::Net& net, const InferenceOptions& o) {
  using namespace cv::dnn;
  const Backend backend = byName<Backend>({{"opencv", DNN_BACKEND_OPENCV},
                                           {"cuda", DNN_BACKEND_CUDA},
                                           {"default", DNN_BACKEND_DEFAULT}},
                                          o.backend, "backend");
  const Target target = byName<Target>({{"cpu", DNN_TARGET_CPU},
                                        {"opencl", DNN_TARGET_OPENCL},
                                        {"opencl_fp16", DNN_TARGET_OPENCL_FP16},
                                        {"cuda", DNN_TARGET_CUDA},
                                        {"cuda_fp16", DNN_TARGET_CUDA_FP16}},
                                       o.target, "target");
  const std::vector<Target> available = getAvailableTargets(backend);
  const bool ok = std::find(available.begin(), available.end(), target) != available.end();
  net.setPreferableBackend(ok ? backend : DNN_BACKEND_OPENCV);
  net.setPreferableTarget(ok ? target : DNN_TARGET_CPU);
  if (ok) return "";
  return "DNN backend " + o.backend + " with target " + o.target +
         " is not available in this OpenCV build (" + cv::getVersionString() +
         "); running on opencv / cpu";
}

}  // namespace

KeypointDetector::KeypointDetector(const std::string& metadata_yaml, DecodeOptions options,
                                   const InferenceOptions& inference)
    : info_(loadModelInfo(metadata_yaml)), options_(options), net_(std::make_unique<Net>()) {
  if (!fs::exists(info_.onnx_path)) throw DetectorError("model file not found: " + info_.onnx_path);
  try {
    net_->net = cv::dnn::readNetFromONNX(info_.onnx_path);
  } catch (const cv::Exception& e) {
    throw DetectorError("OpenCV cannot load " + info_.onnx_path + ": " + e.what());
  }
  inference_note_ = setInference(net_->net, inference);
  // One pass on a blank image checks the output layout against the metadata now, not mid-run.
  const cv::Mat blank(info_.input_height, info_.input_width, CV_8UC3,
                      cv::Scalar::all(info_.letterbox_pad));
  decodeYoloPose(forward(blank, letterboxGeometry(blank.cols, blank.rows, info_.input_width,
                                                  info_.input_height)),
                 info_, Letterbox{}, options_);
}

KeypointDetector::~KeypointDetector() = default;

cv::Mat KeypointDetector::forward(const cv::Mat& rgb, const Letterbox& lb) {
  const cv::Mat input = letterbox(rgb, lb, info_.letterbox_pad);
  net_->net.setInput(cv::dnn::blobFromImage(input, info_.scale, cv::Size(), cv::Scalar(),
                                            info_.swap_rb, false, CV_32F));
  return net_->net.forward();
}

std::vector<Detection> KeypointDetector::detect(const cv::Mat& rgb) {
  if (rgb.empty()) throw DetectorError("detect: empty image");
  if (rgb.type() != CV_8UC3)
    throw DetectorError("detect: expected an 8-bit 3-channel RGB image, got OpenCV type " +
                        std::to_string(rgb.type()));
  const Letterbox lb = letterboxGeometry(rgb.cols, rgb.rows, info_.input_width, info_.input_height);
  return decodeYoloPose(forward(rgb, lb), info_, lb, options_);
}

}  // namespace sgt::detection
