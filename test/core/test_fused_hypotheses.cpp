// Far objects in noisy depth, detected in every frame: at 3 m with three times the demo's depth
// noise (about 4 cm per pixel) a small object's few returns barely constrain its pose, and fits
// that follow them wander. With the detections fused into the track filters
// (fuse_hypotheses), the filters weigh both and the tracks stay nearer the truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr double kDistance = 3.0;       // m in front of the bench
constexpr double kDepthSigma = 0.0044;  // m at 1 m

// Mean distance of the box corners (mm) of a pose from the truth, up to the class's symmetries.
double cornerErrorMm(const ObjectClass& c, const Eigen::Isometry3d& T,
                     const Eigen::Isometry3d& truth) {
  double best = 1e9;
  for (const Eigen::Isometry3d& S : c.symmetry.sampled()) {
    double sum = 0.0;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner =
          c.box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i)).cast<double>();
      sum += (T * S * corner - truth * corner).norm();
    }
    best = std::min(best, 1000.0 * sum / 8.0);
  }
  return best;
}

// Per class, the mean error of its track (cornerErrorMm) over the last 30 of 90 frames.
std::map<std::string, double> errorsOverTheLastSecond(bool fused) {
  const test::StandingView v = test::standingView(kDistance);
  const auto& bench = v.bench;
  PipelineOptions options;
  options.localize = false;
  options.fuse_hypotheses = fused;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::map<std::string, double> mean;
  for (int f = 0; f < 90; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, v.T_map_base, v.cam, v.rays, v.scan, v.T_camera, kDepthSigma, 7100 + f);
    for (std::size_t k = 0; k < bench->classes.size(); ++k) {  // 1 cm, 2 deg
      const Eigen::Vector3d axis(noise(rng), noise(rng), noise(rng));
      const Eigen::Isometry3d T =
          Eigen::Translation3d(0.01 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng))) *
          bench->truth[k] * Eigen::AngleAxisd(0.035 * noise(rng), axis.normalized());
      frame.hypotheses.push_back({bench->classes[k], v.T_map_base.inverse() * T, 0.9});
    }
    for (const TrackedObject& o : pipeline.process(frame).objects) {
      if (f < 60) continue;
      const auto k = static_cast<std::size_t>(
          std::find(bench->classes.begin(), bench->classes.end(), o.class_name) -
          bench->classes.begin());
      mean[o.class_name] +=
          cornerErrorMm(bench->catalog->get(o.class_name), o.T_map_object, bench->truth[k]) / 30.0;
    }
  }
  return mean;
}

TEST(FusedHypotheses, FarObjectsInNoisyDepthStayNearerTheirDetections) {
  const std::map<std::string, double> fused = errorsOverTheLastSecond(true);
  const std::map<std::string, double> alone = errorsOverTheLastSecond(false);
  const test::StandingView v = test::standingView(kDistance);
  for (const std::string& name : v.bench->classes) {
    ASSERT_TRUE(fused.count(name) && alone.count(name)) << name << " not tracked";
    std::printf("%s: fused %.1f mm, fits alone %.1f mm\n", name.c_str(), fused.at(name),
                alone.at(name));
    EXPECT_LT(fused.at(name), alone.at(name) + 0.5) << name;
  }
  // The smallest object, whose few rays constrain it least, gains most.
  EXPECT_LT(fused.at("relay"), 0.6 * alone.at("relay"));
}

}  // namespace
}  // namespace sgt
