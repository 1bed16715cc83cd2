// Near twins in the pipeline: the material box, the multimeter and the relay detected in every
// frame turned by half a turn about their vertical axes (as the shipped keypoint detector turns
// the first two), the robot standing 1.1 m in front of the bench with the demo's depth noise. The
// tracks start turned; with twin tests the depth turns them right and they report themselves sure,
// without they keep the turn.
#include <gtest/gtest.h>

#include <map>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

struct Outcome {
  std::map<std::string, double> error_deg, confidence;
};

Outcome trackTurnedTwins(int twin_tests_per_frame) {
  const test::StandingView v = test::standingView(1.1);
  const auto& bench = v.bench;
  PipelineOptions options;
  options.localize = false;
  options.twin_tests_per_frame = twin_tests_per_frame;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  Outcome out;
  for (int f = 0; f < 90; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, v.T_map_base, v.cam, v.rays, v.scan, v.T_camera, 0.0015, 4100 + f);
    for (std::size_t k = 0; k < bench->classes.size(); ++k) {
      const ObjectClass& c = bench->catalog->get(bench->classes[k]);
      Eigen::Isometry3d half = Eigen::Isometry3d::Identity();
      half.linear() = Eigen::Vector3d(-1, -1, 1).asDiagonal();
      const Eigen::Vector3d centre = c.box.center().cast<double>();
      half.translation() = centre - half.linear() * centre;
      frame.hypotheses.push_back({c.name, v.T_map_base.inverse() * bench->truth[k] * half, 0.9});
    }
    for (const TrackedObject& o : pipeline.process(frame).objects) {
      const auto k = static_cast<std::size_t>(
          std::find(bench->classes.begin(), bench->classes.end(), o.class_name) -
          bench->classes.begin());
      out.error_deg[o.class_name] =
          test::rotationErrorDeg(o.T_map_object.linear(), bench->truth[k].linear());
      out.confidence[o.class_name] = o.orientation_confidence;
    }
  }
  return out;
}

TEST(FramePipelineTwins, TracksStartedOnTheirTwinsTurnRightAndBecomeSure) {
  const Outcome on = trackTurnedTwins(2);
  const Outcome off = trackTurnedTwins(0);
  for (const char* name : {"materialbox", "multimeter", "relay"}) {
    ASSERT_TRUE(on.error_deg.count(name) && off.error_deg.count(name)) << name << " not tracked";
    EXPECT_GT(off.error_deg.at(name), 170.0)
        << name << ": without tests the turn stays (else no test)";
    EXPECT_DOUBLE_EQ(off.confidence.at(name), 1.0) << name;
    EXPECT_LT(on.error_deg.at(name), 10.0) << name;
    EXPECT_GT(on.confidence.at(name), 0.95) << name;
  }
  // The screwdriver has no twin; the crate's, upside down, is plain to see: neither is tested, both
  // stay sure. The crate is untouched. The screwdriver's pose is not compared: its fit sees its
  // neighbours (occlusion and unexplained points near it), which the tests turn.
  EXPECT_NEAR(on.error_deg.at("klt"), off.error_deg.at("klt"), 1e-9);
  EXPECT_DOUBLE_EQ(on.confidence.at("screwdriver"), 1.0);
  EXPECT_GT(on.confidence.at("klt"), 0.999);
}

}  // namespace
}  // namespace sgt
