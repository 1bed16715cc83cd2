// A detector that reports one object twice each frame: the second detection starts a track whose
// model, refined, lies on the first one's. Such a track explains no ray the scene without it does
// not explain as well (registration/twin_evidence.hpp, presenceScore), and is not confirmed.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

// The bench seen from 1.5 m for 40 frames; every object detected where it is, and the multimeter
// also a second time, 2.5 cm beside itself and half turned (the twin a keypoint detector confuses
// it with). Returns how many tracks of each class are confirmed at the end.
std::map<std::string, int> confirmedWithATwiceDetectedMultimeter(double confirm_presence_score) {
  const auto bench = test::benchScene();
  const std::size_t twice = std::find(bench->classes.begin(), bench->classes.end(), "multimeter") -
                            bench->classes.begin();
  const auto [T_map_base, T_map_camera] = test::facingTheBench(*bench, 1.5);
  const PinholeModel cam = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  PipelineOptions options;
  options.localize = false;
  options.confirm_presence_score = confirm_presence_score;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  const SimulatedScan scan = simulate(*bench->world, *rays, T_map_camera);
  Eigen::Isometry3d beside = bench->truth[twice];
  beside.translation().x() += 0.025;
  beside.linear() = beside.linear() * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ());
  std::map<std::string, int> confirmed;
  for (int f = 0; f < 40; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, T_map_base, cam, rays, scan, T_map_camera, 0.0015, 900 + f);
    for (std::size_t k = 0; k < bench->classes.size(); ++k)
      frame.hypotheses.push_back({bench->classes[k], T_map_base.inverse() * bench->truth[k], 0.9});
    frame.hypotheses.push_back({"multimeter", T_map_base.inverse() * beside, 0.8});
    confirmed.clear();
    for (const TrackedObject& o : pipeline.process(frame).objects)
      confirmed[o.class_name] += o.state == TrackState::kConfirmed;
  }
  return confirmed;
}

TEST(DuplicateDetection, ASecondTrackOnATrackedObjectIsNotConfirmed) {
  const auto confirmed =
      confirmedWithATwiceDetectedMultimeter(PipelineOptions{}.confirm_presence_score);
  ASSERT_EQ(confirmed.size(), test::benchScene()->classes.size());
  for (const auto& [name, count] : confirmed) EXPECT_EQ(count, 1) << name;
}

TEST(DuplicateDetection, WithoutThePresenceScoreTheSecondTrackIsConfirmed) {
  // What the test above guards against (else it could not fail).
  EXPECT_EQ(confirmedWithATwiceDetectedMultimeter(0.0).at("multimeter"), 2);
}

}  // namespace
}  // namespace sgt
