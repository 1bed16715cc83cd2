// Appearance randomisation of training renders: surface patterns mix two colours in the stated
// proportions and at the stated scale, and camera effects do what their parameters say.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/simulation/appearance.hpp"

namespace sgt::sim {
namespace {

using Kind = SurfacePattern::Kind;

// Mean weight and the share of neighbouring samples (`step` apart along x) whose weights differ
// by more than 0.25, over a line of points.
std::pair<double, double> sampleLine(const SurfacePattern& p, float step, int n = 4000) {
  double sum = 0.0;
  int changes = 0;
  float last = patternWeight(p, Eigen::Vector3f(0.013f, 0.021f, 0.007f));
  for (int i = 0; i < n; ++i) {
    const float w = patternWeight(p, Eigen::Vector3f(0.013f + i * step, 0.021f, 0.007f));
    EXPECT_GE(w, 0.0f);
    EXPECT_LE(w, 1.0f);
    sum += w;
    changes += std::abs(w - last) > 0.25f;
    last = w;
  }
  return {sum / n, static_cast<double>(changes) / n};
}

TEST(SurfacePattern, EveryKindMixesBothColoursAtItsScale) {
  for (Kind kind : {Kind::kChecker, Kind::kStripes, Kind::kNoise, Kind::kBlotches}) {
    SurfacePattern p;
    p.kind = kind, p.scale = 0.02f, p.seed = 7;
    const auto [mean, fine] = sampleLine(p, 0.001f);  // 20 samples per cell
    EXPECT_GT(mean, 0.2) << int(kind);
    EXPECT_LT(mean, 0.8) << int(kind);
    EXPECT_LT(fine, 0.1) << int(kind);  // smooth at a twentieth of its scale
    p.scale = 0.0013f;  // the same line at a fifteenth of the scale (not a whole ratio: aliasing)
    EXPECT_GT(sampleLine(p, 0.001f).second, fine) << int(kind);
  }
}

TEST(SurfacePattern, NoiseDependsOnItsSeed) {
  SurfacePattern a, b;
  a.kind = b.kind = Kind::kNoise;
  a.seed = 1, b.seed = 2;
  int differ = 0;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3f x(0.037f * i, 0.011f * i, 0.0f);
    EXPECT_EQ(patternWeight(a, x), patternWeight(a, x));
    differ += std::abs(patternWeight(a, x) - patternWeight(b, x)) > 0.05f;
  }
  EXPECT_GT(differ, 50);
}

cv::Mat grey(int level) { return cv::Mat(48, 64, CV_8UC3, cv::Scalar(level, level, level)); }

TEST(CameraEffects, GainWhiteBalanceAndGamma) {
  cv::Mat img = grey(100);
  CameraEffects e;
  e.gain = 1.5f, e.white_balance = Eigen::Vector3f(1.0f, 1.0f, 0.5f);  // RGB: blue halved
  applyCameraEffects(img, e);
  const cv::Vec3b px = img.at<cv::Vec3b>(10, 10);  // BGR
  EXPECT_NEAR(px[2], 150, 1);
  EXPECT_NEAR(px[1], 150, 1);
  EXPECT_NEAR(px[0], 75, 1);
  img = grey(64);
  CameraEffects g;
  g.gamma = 2.0f;  // out = in^(1/2): 0.251 -> 0.501
  applyCameraEffects(img, g);
  EXPECT_NEAR(img.at<cv::Vec3b>(5, 5)[0], 128, 1);
}

TEST(CameraEffects, NoiseBlurAndJpegKeepTheImageAndItsMean) {
  cv::Mat img = grey(120);
  cv::rectangle(img, cv::Rect(20, 10, 20, 20), cv::Scalar(250, 250, 250), cv::FILLED);
  const cv::Scalar before = cv::mean(img);
  CameraEffects e;
  e.noise_sigma = 6.0f, e.blur_sigma = 1.0f, e.jpeg_quality = 60, e.seed = 3;
  cv::Mat out = img.clone();
  applyCameraEffects(out, e);
  ASSERT_EQ(out.size(), img.size());
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_NEAR(cv::mean(out)[0], before[0], 2.0);
  cv::Mat diff;
  cv::absdiff(out, img, diff);
  EXPECT_GT(cv::mean(diff)[0], 2.0);             // noisy
  EXPECT_LT(out.at<cv::Vec3b>(20, 20)[0], 250);  // the square's edge is blurred into its inside
  EXPECT_GT(out.at<cv::Vec3b>(20, 19)[0], 130);  // and out of it
}

}  // namespace
}  // namespace sgt::sim
