// Evidence of absence in noisy depth. At 3 m with three times the demo's depth noise (about 4 cm
// per pixel) most returns of a present object lie farther from its surface than any fit
// threshold: as many before it as beyond it. Only the rays measured beyond it show it missing,
// so the rays measured before it (absence_noise_sigmas) count against absence. Present objects
// then keep their tracks while detections hold them; a detection where nothing stands still goes.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr double kDistance = 3.0;       // m in front of the bench
constexpr double kDepthSigma = 0.0044;  // m at 1 m

// A detection of `truth` with 1 cm and 2 deg of noise, in the base frame.
PoseHypothesis noisyDetection(const std::string& name, const Eigen::Isometry3d& truth,
                              const Eigen::Isometry3d& T_map_base, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d axis(n(rng), n(rng), n(rng));
  const Eigen::Isometry3d T = Eigen::Translation3d(0.01 * Eigen::Vector3d(n(rng), n(rng), n(rng))) *
                              truth * Eigen::AngleAxisd(0.035 * n(rng), axis.normalized());
  return {name, T_map_base.inverse() * T, 0.9};
}

// Per class over 90 frames of detections of every object: the track ids it got, and the share of
// frames in which its fit failed.
struct Tracked {
  std::set<std::string> ids;
  double failed_fits = 0.0;
};
std::map<std::string, Tracked> trackEveryObject() {
  const test::StandingView v = test::standingView(kDistance);
  const auto& bench = v.bench;
  PipelineOptions options;
  options.localize = false;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  std::mt19937 rng(5);
  std::map<std::string, Tracked> tracked;
  for (int f = 0; f < 90; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, v.T_map_base, v.cam, v.rays, v.scan, v.T_camera, kDepthSigma, 9100 + f);
    for (std::size_t k = 0; k < bench->classes.size(); ++k)
      frame.hypotheses.push_back(
          noisyDetection(bench->classes[k], bench->truth[k], v.T_map_base, rng));
    for (const TrackedObject& o : pipeline.process(frame).objects) {
      tracked[o.class_name].ids.insert(o.id);
      tracked[o.class_name].failed_fits += (o.quality.status != RefineStatus::kOk) / 90.0;
    }
  }
  return tracked;
}

TEST(AbsenceInNoise, PresentObjectsKeepOneTrackEachThoughTheirFitsFail) {
  const std::map<std::string, Tracked> tracked = trackEveryObject();
  const std::unique_ptr<test::BenchScene> bench = test::benchScene();
  for (const std::string& name : bench->classes) {
    ASSERT_TRUE(tracked.count(name)) << name << " not tracked";
    const Tracked& t = tracked.at(name);
    std::printf("%s: %zu track(s), fit failed in %.0f %% of the frames\n", name.c_str(),
                t.ids.size(), 100.0 * t.failed_fits);
    EXPECT_EQ(t.ids.size(), 1u) << name;
  }
  // The material box's fits explain too few of its rays to tell it is there: a false hypothesis
  // by the fit's bound, which is no evidence of absence.
  EXPECT_GT(tracked.at("materialbox").failed_fits, 0.8);
}

TEST(AbsenceInNoise, ADetectionWhereNothingStandsGoes) {
  const test::StandingView v = test::standingView(kDistance);
  const auto& bench = v.bench;
  PipelineOptions options;
  options.localize = false;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  // A multimeter on the empty bench top in front of the row of objects, detected once.
  const ObjectClass& c = bench->catalog->get("multimeter");
  const double half_z = 0.5 * c.box.sizes().z() - c.box.center().z();
  const Eigen::Isometry3d nowhere =
      Eigen::Translation3d(bench->top + Eigen::Vector3d(-0.1, 0.25, half_z + 0.001)) *
      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  std::mt19937 rng(3);
  int last_seen = -1;
  for (int f = 0; f < 30; ++f) {  // 1 s: the stale timeout alone would keep it
    PipelineFrame frame =
        test::depthFrame(f, v.T_map_base, v.cam, v.rays, v.scan, v.T_camera, kDepthSigma, 9300 + f);
    if (f == 0)
      frame.hypotheses.push_back(noisyDetection("multimeter", nowhere, v.T_map_base, rng));
    for (const TrackedObject& o : pipeline.process(frame).objects)
      if (o.class_name == "multimeter") last_seen = f;
  }
  ASSERT_GE(last_seen, 0) << "the detection made no track";
  EXPECT_LT(last_seen, 20) << "kept for " << last_seen + 1 << " frames";
}

}  // namespace
}  // namespace sgt
