// Tracks seen missing keep their ids for the next detection of their class that no track takes:
// a carried object comes back elsewhere under the id it had.
#include <gtest/gtest.h>

#include <set>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "scene_graph_tracker/tracking/unlocated_tracks.hpp"
#include "support.hpp"

namespace sgt {
namespace {

TEST(UnlocatedTracks, AnIdGoesToTheNearestDetectionOfItsClassUntilFoundOrExpired) {
  UnlocatedTracks u;
  u.add("relay_1", "relay", {0, 0, 0}, 1.0);
  u.add("relay_2", "relay", {1, 0, 0}, 2.0);
  EXPECT_EQ(u.claim("klt", {1, 0, 0}), "");
  EXPECT_EQ(u.claim("relay", {0.8, 0, 0}), "relay_2");
  EXPECT_EQ(u.claim("relay", {0.8, 0, 0}), "relay_1") << "relay_2 is claimed";
  EXPECT_EQ(u.claim("relay", {0.8, 0, 0}), "");
  u.release("relay_2");  // its tentative track went
  u.found("relay_1");    // its track was confirmed
  EXPECT_EQ(u.size(), 1u);
  u.expire(61.9, 60.0);
  EXPECT_EQ(u.size(), 1u);
  u.expire(62.1, 60.0);
  EXPECT_EQ(u.size(), 0u);
}

// The bench seen from 1.5 m; every object detected in every frame but the multimeter while it is
// carried: it leaves its place at frame 30 (1 s) and is put down 0.9 m away at frame `back`. The
// ids of its confirmed tracks.
std::vector<std::string> multimeterIds(double unlocated_keep_s, int back) {
  test::StandingView v = test::standingView(1.5);
  test::BenchScene& bench = *v.bench;
  PipelineOptions options;
  options.localize = false;
  options.unlocated_keep_s = unlocated_keep_s;
  FramePipeline pipeline(bench.catalog, bench.map, options);
  const ObjectClass& c = bench.catalog->get("multimeter");
  const Eigen::Isometry3d elsewhere =
      Eigen::Translation3d(
          bench.top +
          Eigen::Vector3d(0.45, 0.25, 0.5 * c.box.sizes().z() - c.box.center().z() + 0.001)) *
      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  std::vector<std::string> ids;
  for (int f = 0; f < 150; ++f) {
    if (f == 30) {  // picked up and carried out of view
      bench.world->setInstanceEnabled(test::BenchScene::objectNode(0), false);
      bench.world->commit();
      v.scan = simulate(*bench.world, *v.rays, v.T_camera);
    } else if (f == back) {  // put down elsewhere
      bench.world->setInstancePose(test::BenchScene::objectNode(0), elsewhere);
      bench.world->setInstanceEnabled(test::BenchScene::objectNode(0), true);
      bench.world->commit();
      bench.truth[0] = elsewhere;
      v.scan = simulate(*bench.world, *v.rays, v.T_camera);
    }
    PipelineFrame frame =
        test::depthFrame(f, v.T_map_base, v.cam, v.rays, v.scan, v.T_camera, 0.0015, 700 + f);
    for (std::size_t k = 0; k < bench.classes.size(); ++k)
      if (k != 0 || f < 30 || f >= back)
        frame.hypotheses.push_back(
            {bench.classes[k], v.T_map_base.inverse() * bench.truth[k], 0.9});
    for (const TrackedObject& o : pipeline.process(frame).objects)
      if (o.class_name == "multimeter" && o.state == TrackState::kConfirmed &&
          (ids.empty() || ids.back() != o.id))
        ids.push_back(o.id);
  }
  return ids;
}

TEST(UnlocatedTracks, AnObjectCarriedAwayComesBackUnderItsId) {
  // Back after its track went (seen missing for remove_after): the waiting id.
  EXPECT_EQ(multimeterIds(60.0, 90), std::vector<std::string>({"multimeter_1"}));
  EXPECT_EQ(multimeterIds(0.0, 90), std::vector<std::string>({"multimeter_1", "multimeter_2"}))
      << "without: a new id";
}

}  // namespace
}  // namespace sgt
