// The keypoint detector's pre- and post-processing: letterbox geometry, decoding a hand-made
// YOLOv8-pose output tensor, class-aware NMS, metadata checks.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "support.hpp"

using namespace sgt::detection;

namespace {

ModelInfo twoClassInfo(int keypoints = 2) {
  ModelInfo info;
  info.input_width = 320;
  info.input_height = 320;
  info.names = {"relay", "klt"};
  info.keypoints = keypoints;
  return info;
}

// Output blob 1 x C x N filled with zeros; anchors are set by hand.
struct Blob {
  Blob(const ModelInfo& info, int anchors) : info(info), n(anchors) {
    const int sizes[3] = {1, info.channels(), anchors};
    mat = cv::Mat(3, sizes, CV_32F, cv::Scalar(0));
  }
  float& at(int c, int a) { return mat.ptr<float>()[c * n + a]; }
  void set(int a, Eigen::Vector4f box, int cls, float score,
           const std::vector<Eigen::Vector3f>& kps) {
    for (int i = 0; i < 4; ++i) at(i, a) = box[i];
    at(4 + cls, a) = score;
    const int nc = static_cast<int>(info.names.size());
    for (std::size_t k = 0; k < kps.size(); ++k)
      for (int j = 0; j < 3; ++j) at(4 + nc + 3 * static_cast<int>(k) + j, a) = kps[k][j];
  }
  ModelInfo info;
  int n;
  cv::Mat mat;
};

}  // namespace

TEST(Letterbox, GeometryOf640x480Into320Square) {
  const Letterbox lb = letterboxGeometry(640, 480, 320, 320);
  EXPECT_DOUBLE_EQ(lb.scale, 0.5);
  EXPECT_DOUBLE_EQ(lb.pad_x, 0.0);
  EXPECT_DOUBLE_EQ(lb.pad_y, 40.0);  // 240 rows of image, 40 grey rows above and below
  const Eigen::Vector2d p(123.25, 401.5);
  EXPECT_TRUE(lb.toImage(lb.toInput(p)).isApprox(p, 1e-12));
  EXPECT_TRUE(lb.toInput(Eigen::Vector2d(0, 0)).isApprox(Eigen::Vector2d(0, 40)));
  EXPECT_TRUE(lb.toInput(Eigen::Vector2d(640, 480)).isApprox(Eigen::Vector2d(320, 280)));
}

TEST(Letterbox, ImageLandsWherePixelsMapAndPaddingIsGrey) {
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  img(cv::Rect(200, 100, 40, 40))
      .setTo(cv::Scalar(255, 255, 255));  // white square 200..240 x 100..140
  const Letterbox lb = letterboxGeometry(img.cols, img.rows, 320, 320);
  const cv::Mat in = letterbox(img, lb, 114);
  ASSERT_EQ(in.rows, 320);
  ASSERT_EQ(in.cols, 320);
  EXPECT_EQ(in.at<cv::Vec3b>(5, 5), cv::Vec3b(114, 114, 114));    // padding above
  EXPECT_EQ(in.at<cv::Vec3b>(315, 5), cv::Vec3b(114, 114, 114));  // padding below
  const Eigen::Vector2d centre = lb.toInput(Eigen::Vector2d(220, 120));
  EXPECT_EQ(in.at<cv::Vec3b>(static_cast<int>(centre.y()), static_cast<int>(centre.x())),
            cv::Vec3b(255, 255, 255));
  EXPECT_EQ(in.at<cv::Vec3b>(static_cast<int>(centre.y()), static_cast<int>(centre.x()) + 20),
            cv::Vec3b(0, 0, 0));
}

TEST(Letterbox, PortraitImagePadsLeftAndRight) {
  const Letterbox lb = letterboxGeometry(300, 600, 320, 320);
  EXPECT_DOUBLE_EQ(lb.scale, 320.0 / 600.0);
  EXPECT_DOUBLE_EQ(lb.pad_y, 0.0);
  EXPECT_DOUBLE_EQ(lb.pad_x, 80.0);
  EXPECT_THROW(letterboxGeometry(0, 10, 320, 320), DetectorError);
}

TEST(DecodeYoloPose, HandMadeTensorGivesBoxesAndKeypointsInImagePixels) {
  const ModelInfo info = twoClassInfo();
  Blob blob(info, 6);
  // Anchor 1: a relay box centred at input (100, 140), 40 x 60, score 0.9, keypoints visible.
  blob.set(1, {100, 140, 40, 60}, 0, 0.9f, {{90, 120, 0.95f}, {110, 160, 0.2f}});
  // Anchor 4: a klt box, score 0.7.
  blob.set(4, {250, 200, 80, 40}, 1, 0.7f, {{230, 190, 0.9f}, {270, 210, 0.9f}});
  // Anchor 3: below the threshold.
  blob.set(3, {50, 50, 10, 10}, 1, 0.2f, {});
  const Letterbox lb = letterboxGeometry(640, 480, 320, 320);
  DecodeOptions opt;
  opt.score_threshold = 0.5f;
  const auto dets = decodeYoloPose(blob.mat, info, lb, opt);
  ASSERT_EQ(dets.size(), 2u);
  const Detection& relay = dets[0];  // sorted by score
  EXPECT_EQ(relay.class_name, "relay");
  EXPECT_EQ(relay.class_id, 0);
  EXPECT_FLOAT_EQ(relay.score, 0.9f);
  // input (80..120, 110..170) → continuous image ((80-0)*2, (110-40)*2) ... → pixel centres -0.5
  EXPECT_TRUE(relay.box_min.isApprox(Eigen::Vector2d(159.5, 139.5)));
  EXPECT_TRUE(relay.box_max.isApprox(Eigen::Vector2d(239.5, 259.5)));
  ASSERT_EQ(relay.keypoints.size(), 2u);
  EXPECT_TRUE(relay.keypoints[0].px.isApprox(Eigen::Vector2d(179.5, 159.5)));
  EXPECT_FLOAT_EQ(relay.keypoints[0].visibility, 0.95f);
  EXPECT_TRUE(relay.keypoints[1].px.isApprox(Eigen::Vector2d(219.5, 239.5)));
  EXPECT_FLOAT_EQ(relay.keypoints[1].visibility, 0.2f);
  EXPECT_EQ(dets[1].class_name, "klt");
  EXPECT_TRUE(dets[1].box_min.isApprox(Eigen::Vector2d(419.5, 279.5)));
}

TEST(DecodeYoloPose, WrongChannelCountIsRefusedWithTheNumbers) {
  ModelInfo info = twoClassInfo();
  Blob blob(info, 4);
  info.names.push_back("screwdriver");  // metadata says 3 classes, the tensor has 2
  try {
    decodeYoloPose(blob.mat, info, letterboxGeometry(640, 480, 320, 320), {});
    FAIL() << "expected DetectorError";
  } catch (const DetectorError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("has 12 channels"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 + 3 classes + 2 keypoints x 3 = 13"), std::string::npos) << msg;
  }
  const int sizes2[2] = {14, 4};
  EXPECT_THROW(decodeYoloPose(cv::Mat(2, sizes2, CV_32F, cv::Scalar(0)), twoClassInfo(), {}, {}),
               DetectorError);
}

TEST(DecodeYoloPose, NanScoresAreDropped) {
  const ModelInfo info = twoClassInfo();
  Blob blob(info, 2);
  blob.set(0, {10, 10, 5, 5}, 0, std::numeric_limits<float>::quiet_NaN(), {});
  EXPECT_TRUE(decodeYoloPose(blob.mat, info, letterboxGeometry(320, 320, 320, 320), {}).empty());
}

TEST(DecodeYoloPose, PerClassScoreThresholdsRaiseTheGlobalOne) {
  ModelInfo info = twoClassInfo(0);
  info.score_thresholds = {{"klt", 0.6f}};
  Blob blob(info, 4);
  blob.set(0, {50, 50, 10, 10}, 0, 0.5f, {});    // relay 0.5: the global 0.35 applies, kept
  blob.set(1, {150, 50, 10, 10}, 1, 0.5f, {});   // klt 0.5 < its 0.6: dropped
  blob.set(2, {250, 50, 10, 10}, 1, 0.65f, {});  // klt 0.65: kept
  blob.set(3, {50, 150, 10, 10}, 0, 0.3f, {});   // relay below the global: dropped
  const Letterbox lb = letterboxGeometry(320, 320, 320, 320);
  DecodeOptions opt;
  opt.score_threshold = 0.35f;
  auto dets = decodeYoloPose(blob.mat, info, lb, opt);
  ASSERT_EQ(dets.size(), 2u);
  EXPECT_EQ(dets[0].class_name, "klt");
  EXPECT_FLOAT_EQ(dets[0].score, 0.65f);
  EXPECT_EQ(dets[1].class_name, "relay");
  opt.score_threshold = 0.7f;  // a global threshold above a class's entry wins
  dets = decodeYoloPose(blob.mat, info, lb, opt);
  EXPECT_TRUE(dets.empty());
}

TEST(Nms, SuppressesOverlapsOfTheSameClassOnly) {
  const auto det = [](int cls, float score, double x0, double y0, double x1, double y1) {
    Detection d;
    d.class_id = cls;
    d.score = score;
    d.box_min = {x0, y0};
    d.box_max = {x1, y1};
    return d;
  };
  std::vector<Detection> in = {
      det(0, 0.6f, 0, 0, 100, 100),      // overlaps the 0.9 one (IoU 0.81): suppressed
      det(0, 0.9f, 5, 5, 105, 105),      // best
      det(1, 0.8f, 0, 0, 100, 100),      // other class, same place: kept
      det(0, 0.5f, 200, 200, 250, 250),  // far away: kept
      det(0, 0.7f, 60, 60, 160, 160),    // IoU with best ≈ 0.25: kept
  };
  const auto out = nonMaximumSuppression(in, 0.5f, 10);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_FLOAT_EQ(out[0].score, 0.9f);
  EXPECT_FLOAT_EQ(out[1].score, 0.8f);
  EXPECT_FLOAT_EQ(out[2].score, 0.7f);
  EXPECT_FLOAT_EQ(out[3].score, 0.5f);
  EXPECT_NEAR(iou(in[0], in[1]), 9025.0 / (20000.0 - 9025.0), 1e-12);
  EXPECT_EQ(nonMaximumSuppression(in, 0.5f, 2).size(), 2u);
}

TEST(ModelInfo, LoadsMetadataAndNamesMissingKeys) {
  const std::string good = sgt::test::writeFile(
      "m.yaml", "input_width: 320\ninput_height: 256\nnames: [a, b, c]\nkeypoints: 9\n");
  const ModelInfo info = loadModelInfo(good);
  EXPECT_EQ(info.input_height, 256);
  EXPECT_EQ(info.names.size(), 3u);
  EXPECT_EQ(info.channels(), 4 + 3 + 27);
  EXPECT_EQ(info.onnx_path.substr(info.onnx_path.size() - 7), "/m.onnx");
  const std::string bad =
      sgt::test::writeFile("bad.yaml", "input_width: 320\ninput_height: 256\nkeypoints: 9\n");
  try {
    loadModelInfo(bad);
    FAIL();
  } catch (const DetectorError& e) {
    EXPECT_NE(std::string(e.what()).find("missing 'names'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(KeypointDetector{good}, DetectorError);  // m.onnx does not exist
  const std::string thresholds =
      sgt::test::writeFile("t.yaml",
                           "input_width: 320\ninput_height: 256\nnames: [a, b]\nkeypoints: "
                           "9\nscore_thresholds: {b: 0.6}\n");
  EXPECT_FLOAT_EQ(loadModelInfo(thresholds).score_thresholds.at("b"), 0.6f);
  const std::string unknown =
      sgt::test::writeFile("u.yaml",
                           "input_width: 320\ninput_height: 256\nnames: [a, b]\nkeypoints: "
                           "9\nscore_thresholds: {c: 0.6}\n");
  try {
    loadModelInfo(unknown);
    FAIL();
  } catch (const DetectorError& e) {
    EXPECT_NE(std::string(e.what()).find("'c', not one of its classes"), std::string::npos)
        << e.what();
  }
}
