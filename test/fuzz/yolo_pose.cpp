// The keypoint model's output decoding (sgt::detection::decodeYoloPose): a raw output blob (its
// dims, type and floats from the bytes: usually 1 x C x N with C what the metadata expects) with
// metadata as loadModelInfo accepts it (1..8 classes, 0..12 keypoints, a positive input size,
// sometimes per-class score thresholds), the letterbox of an image size from the bytes, and
// decoding options from the bytes.
#include <algorithm>
#include <opencv2/core.hpp>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/detection/keypoint_detector.hpp"

namespace {

namespace det = sgt::detection;
using sgt::fuzz::number;

det::ModelInfo modelInfo(FuzzedDataProvider& p) {
  det::ModelInfo info;
  info.input_width = p.ConsumeIntegralInRange<int>(1, 640);
  info.input_height = p.ConsumeIntegralInRange<int>(1, 640);
  info.names.resize(p.ConsumeIntegralInRange<int>(1, 8));
  for (std::size_t c = 0; c < info.names.size(); ++c) info.names[c] = "class" + std::to_string(c);
  info.keypoints = p.ConsumeIntegralInRange<int>(0, 12);
  if (p.ConsumeBool())
    for (const std::string& n : info.names)
      if (p.ConsumeBool()) info.score_thresholds[n] = static_cast<float>(number(p, 1.0));
  return info;
}

det::DecodeOptions decodeOptions(FuzzedDataProvider& p) {
  det::DecodeOptions o;
  if (p.ConsumeBool()) return o;
  o.score_threshold = static_cast<float>(number(p, 1.0));
  o.nms_iou = static_cast<float>(number(p, 1.0));
  o.max_detections =
      p.ConsumeBool() ? p.ConsumeIntegralInRange<int>(0, 20) : p.ConsumeIntegral<int>();
  return o;
}

// The blob: 1 x C x N floats (sometimes other dims or types); at most 64k elements.
cv::Mat output(FuzzedDataProvider& p, const det::ModelInfo& info) {
  int dims = 3, type = CV_32F;
  if (p.ConsumeIntegralInRange<int>(0, 15) == 0) dims = p.ConsumeIntegralInRange<int>(1, 4);
  if (p.ConsumeIntegralInRange<int>(0, 15) == 0) type = p.PickValueInArray({CV_64F, CV_8U, CV_32S});
  std::vector<int> size(dims, 1);
  if (dims >= 2)
    size[1] = p.ConsumeIntegralInRange<int>(0, 7) != 0 ? info.channels()
                                                       : p.ConsumeIntegralInRange<int>(1, 64);
  if (dims >= 3) size[2] = p.ConsumeIntegralInRange<int>(1, 64);
  if (p.ConsumeIntegralInRange<int>(0, 15) == 0) size[0] = p.ConsumeIntegralInRange<int>(1, 3);
  std::size_t total = 1;
  for (int s : size) total *= s;
  if (total > (1u << 16)) size.back() = 1;
  cv::Mat m(dims, size.data(), type, cv::Scalar(0));
  // The values: floats from the bytes (an anchor's score in 0..1 often enough to pass).
  if (type == CV_32F) {
    float* v = m.ptr<float>();
    for (std::size_t i = 0; i < m.total() && p.remaining_bytes() > 0; ++i)
      v[i] = p.ConsumeBool() ? p.ConsumeFloatingPointInRange(0.0f, 1.0f)
                             : static_cast<float>(number(p, 400.0));
  }
  return m;
}

}  // namespace

int sgtFuzzYoloPose(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  const det::ModelInfo info = modelInfo(p);
  const det::DecodeOptions options = decodeOptions(p);
  const int image_width = p.ConsumeIntegralInRange<int>(-1, 2000);
  const int image_height = p.ConsumeIntegralInRange<int>(-1, 2000);
  det::Letterbox lb;
  try {
    lb = det::letterboxGeometry(image_width, image_height, info.input_width, info.input_height);
  } catch (const det::DetectorError&) {
    return 0;
  }
  const cv::Mat blob = output(p, info);
  try {
    const std::vector<det::Detection> found = det::decodeYoloPose(blob, info, lb, options);
    sgt::fuzz::expect(static_cast<int>(found.size()) <= std::max(options.max_detections, 0),
                      "at most max_detections detections");
    for (const det::Detection& d : found)
      sgt::fuzz::expect(d.class_id >= 0 && d.class_id < static_cast<int>(info.names.size()) &&
                            d.keypoints.size() == static_cast<std::size_t>(info.keypoints),
                        "detections of a known class with every keypoint");
  } catch (const det::DetectorError&) {
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzYoloPose)
