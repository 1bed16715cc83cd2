// The model the package ships (models/sgt_keypoints.{onnx,yaml}) loads in this OpenCV, fits its
// metadata, runs in the detector and finds the objects of a shipped test image: a held-out frame
// rendered by render_dataset (seed 2, never trained on), with its labels and poses.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/detection/pose_detector.hpp"
#include "support.hpp"

namespace sgt::detection {
namespace {

const std::string kDir = std::string(SGT_SOURCE_DIR) + "/test/data/detector/";

struct Truth {
  std::string class_name;
  Eigen::Vector2d box_min, box_max;
  Eigen::Vector3d t_camera_object;
};

std::vector<Truth> readTruth(PinholeModel& cam) {
  const YAML::Node j = YAML::LoadFile(kDir + "frame.json");
  cam.width = j["width"].as<int>(), cam.height = j["height"].as<int>();
  cam.fx = j["K"][0].as<double>(), cam.cx = j["K"][2].as<double>(), cam.fy = j["K"][4].as<double>(),
  cam.cy = j["K"][5].as<double>();
  std::vector<Truth> out;
  std::ifstream labels(kDir + "frame.txt");
  for (const auto& o : j["objects"]) {
    Truth t;
    t.class_name = o["class"].as<std::string>();
    for (int r = 0; r < 3; ++r) t.t_camera_object[r] = o["T_camera_object"][r][3].as<double>();
    double cls, cx, cy, w, h, k;
    labels >> cls >> cx >> cy >> w >> h;
    for (int i = 0; i < 27; ++i) labels >> k;
    t.box_min = Eigen::Vector2d((cx - w / 2) * cam.width - 0.5, (cy - h / 2) * cam.height - 0.5);
    t.box_max = Eigen::Vector2d((cx + w / 2) * cam.width - 0.5, (cy + h / 2) * cam.height - 0.5);
    out.push_back(t);
  }
  return out;
}

TEST(ShippedModel, LoadsAndFitsItsMetadata) {
  const ModelInfo info = loadModelInfo(std::string(SGT_SOURCE_DIR) + "/models/sgt_keypoints.yaml");
  EXPECT_EQ(info.keypoints, kCuboidKeypoints);
  EXPECT_EQ(info.keypoint_order, "dope_cuboid");
  EXPECT_EQ(info.names,
            (std::vector<std::string>{"multimeter", "screwdriver", "materialbox", "klt", "relay"}));
  KeypointDetector detector(std::string(SGT_SOURCE_DIR) +
                            "/models/sgt_keypoints.yaml");  // runs one pass
  std::ifstream onnx(info.onnx_path, std::ios::binary | std::ios::ate);
  EXPECT_LT(static_cast<double>(onnx.tellg()), 10e6) << "the shipped model must stay under 10 MB";
}

// A backend / target this OpenCV cannot run falls back to opencv / cpu with a note, and detects
// exactly what the default does; unknown names are refused.
TEST(ShippedModel, UnavailableInferenceTargetFallsBackToTheCpu) {
  const std::string yaml = std::string(SGT_SOURCE_DIR) + "/models/sgt_keypoints.yaml";
  const auto cuda = cv::dnn::getAvailableTargets(cv::dnn::DNN_BACKEND_CUDA);
  KeypointDetector asked(yaml, {}, InferenceOptions{"cuda", "cuda_fp16"});
  if (cuda.empty()) {
    EXPECT_NE(asked.inferenceNote().find("not available"), std::string::npos)
        << asked.inferenceNote();
    cv::Mat bgr = cv::imread(kDir + "frame.png", cv::IMREAD_COLOR), rgb;
    ASSERT_FALSE(bgr.empty());
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    KeypointDetector cpu(yaml);
    EXPECT_TRUE(cpu.inferenceNote().empty());
    const auto a = asked.detect(rgb), b = cpu.detect(rgb);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].score, b[k].score);
  }
  EXPECT_THROW(KeypointDetector(yaml, {}, InferenceOptions{"tensorrt", "cpu"}), DetectorError);
  EXPECT_THROW(KeypointDetector(yaml, {}, InferenceOptions{"opencv", "gpu"}), DetectorError);
}

TEST(ShippedModel, FindsTheObjectsOfAHeldOutRender) {
  PinholeModel cam;
  const auto truth = readTruth(cam);
  ASSERT_GE(truth.size(), 3u);
  cv::Mat bgr = cv::imread(kDir + "frame.png", cv::IMREAD_COLOR), rgb;
  ASSERT_FALSE(bgr.empty());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const ObjectCatalog catalog =
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml");
  PoseDetector detector(std::string(SGT_SOURCE_DIR) + "/models/sgt_keypoints.yaml", catalog);
  const auto dets = detector.detect(rgb, cam);
  std::size_t found = 0, located = 0;
  for (const Truth& t : truth) {
    Detection tb;
    tb.box_min = t.box_min, tb.box_max = t.box_max;
    for (const auto& d : dets) {
      if (d.detection.class_name != t.class_name || iou(d.detection, tb) < 0.5) continue;
      ++found;
      if (d.pnp.ok() && (d.pnp.T_camera_object.translation() - t.t_camera_object).norm() < 0.1)
        ++located;
      break;
    }
  }
  std::cout << "[ figures  ] " << found << " of " << truth.size()
            << " objects found (IoU >= 0.5, right class), " << located
            << " with a PnP pose within 10 cm; " << dets.size() << " detections\n";
  // The shipped model found 4 of the 6 objects here when it was committed
  // (test/data/detector/README).
  EXPECT_GE(found, 3u) << "the shipped model no longer finds the objects of its test image";
}

}  // namespace
}  // namespace sgt::detection
