// Track life cycle on a simulated 15 Hz sequence of the workbench (robot standing, pose known):
//  0.0–1.0 s  detections of all five objects every frame → confirmed tracks;
//  1.0–2.0 s  the detector drops out completely for 1 s → every track coasts on its refinement,
//             stays listed and stays accurate;
//  2.0–2.5 s  detections again;
//  2.5–4.5 s  the materialbox is taken away (gone from the world, no detections) → its track is
//             removed within ~1 s; at the same moment a board the catalog does not know is put in
//             front of the multimeter (no detections either) → that track is only occluded and
//             must not be removed.
#include <gtest/gtest.h>

#include <random>

#include "scene_graph_tracker/evaluation/pose_metrics.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

const TrackedObject* findClass(const PipelineResult& r, const std::string& class_name) {
  for (const auto& o : r.objects)
    if (o.class_name == class_name) return &o;
  return nullptr;
}

TEST(TrackLifecycle, CoastsThroughADropoutRemovesWhatIsGoneKeepsWhatIsHidden) {
  const auto bench = test::benchScene();
  RaycastScene& world = *bench->world;
  const std::size_t kMaterialbox = 2, kMultimeter = 0;
  // The board: 30 x 30 cm, 4 cm thick, standing on the bench 25 cm in front of the multimeter
  // (towards the robot), disabled until the take-away.
  const NodeId board = 40;
  const Eigen::Vector3d to_robot =
      (bench->T_map_base.translation() - bench->truth[kMultimeter].translation())
          .cwiseProduct(Eigen::Vector3d(1, 1, 0))
          .normalized();
  Eigen::Isometry3d T_board = test::poseXyzYaw(
      bench->truth[kMultimeter].translation() + 0.25 * to_robot + Eigen::Vector3d(0, 0, 0.13),
      std::atan2(to_robot.y(), to_robot.x()));
  world.addInstance(
      board, world.addMesh(std::make_shared<TriangleMesh>(makeBox({0.04f, 0.3f, 0.3f}))), T_board);
  world.setInstanceEnabled(board, false);
  world.commit();

  PipelineOptions options;
  options.localize = false;  // the robot pose is known here: this test is about tracks
  FramePipeline pipeline(bench->catalog, bench->map, options);
  const Eigen::Isometry3d T_odom_base = bench->T_map_base;  // map == odom
  const PinholeModel cam = PinholeModel::xtion();
  auto cam_rays = std::make_shared<SensorRays>(makeRays(cam));
  std::mt19937 rng(11);
  std::normal_distribution<double> g;

  const int kRate = 15, kTakenFrame = 38;  // taken away at 2.53 s
  const double taken_at = static_cast<double>(kTakenFrame) / kRate;
  double coast_error_max = 0.0, removed_at = -1.0;
  bool all_listed_in_dropout = true, multimeter_removed = false;
  for (int f = 0; f <= 67; ++f) {
    const double t = static_cast<double>(f) / kRate;
    const bool gone = f >= kTakenFrame;
    if (f == kTakenFrame) {
      world.setInstanceEnabled(test::BenchScene::objectNode(kMaterialbox), false);
      world.setInstanceEnabled(board, true);
      world.commit();
    }
    PipelineFrame frame;
    frame.stamp = t;
    frame.T_odom_base = T_odom_base;
    const SimulatedScan scan = simulate(world, *cam_rays, bench->T_map_base * bench->T_base_camera);
    frame.measurements.push_back(fromDepthImage(cam, cam_rays, depthImage(scan, *cam_rays),
                                                T_odom_base * bench->T_base_camera));
    addDepthNoise(frame.measurements.back(), 0.0015, 300 + f);
    const bool dropout = t >= 1.0 && t < 2.0;
    for (std::size_t k = 0; k < bench->classes.size() && !dropout; ++k) {
      if (gone && (k == kMaterialbox || k == kMultimeter)) continue;
      Eigen::Isometry3d T = bench->truth[k];
      T.translation() += 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      frame.hypotheses.push_back({bench->classes[k], bench->T_map_base.inverse() * T, 0.9});
    }
    const PipelineResult r = pipeline.process(frame);
    if (dropout) {
      for (std::size_t k = 0; k < bench->classes.size(); ++k) {
        const TrackedObject* o = findClass(r, bench->classes[k]);
        if (!o) {
          all_listed_in_dropout = false;
          continue;
        }
        const ObjectClass& c = bench->catalog->get(o->class_name);
        coast_error_max = std::max(
            coast_error_max,
            poseErrors(c, sampleSurface(*c.mesh, 200, 1).points, o->T_map_object, bench->truth[k])
                .add_s);
      }
    }
    if (gone && removed_at < 0 && !findClass(r, "materialbox")) removed_at = t;
    if (gone && !findClass(r, "multimeter")) multimeter_removed = true;
    if (t > 0.5 && t < taken_at) {
      ASSERT_EQ(r.objects.size(), 5u) << "at t = " << t;
    }
  }
  std::cout << "[ figures  ] dropout 1 s: worst ADD-S " << coast_error_max * 1000
            << " mm; taken away: removed after " << (removed_at - taken_at)
            << " s; occluded multimeter kept: " << (multimeter_removed ? "no" : "yes") << "\n";
  EXPECT_TRUE(all_listed_in_dropout) << "a track vanished during the detector dropout";
  EXPECT_LT(coast_error_max, 0.005) << "coasting tracks must stay at refinement accuracy";
  ASSERT_GT(removed_at, 0.0) << "the materialbox track was never removed";
  EXPECT_GT(removed_at - taken_at, 0.5) << "removed too early: evidence of absence needs time";
  EXPECT_LE(removed_at - taken_at, 1.2) << "the issue asks for removal within ~1 s";
  EXPECT_FALSE(multimeter_removed) << "an occluded object's track must not be removed";
}

// A track mostly hidden behind another *tracked* object still takes evidence of absence from the
// rays that reach it: the multimeter vanishes at the moment a second material box (a track)
// covers most of it, and the sliver of rays past the box sees through where it was. It is
// removed while still covered, within ~1 s, not kept until the box goes at 3 s.
double removedWhileHiddenAt(double& removed_after_covered) {
  const auto bench = test::benchScene();
  RaycastScene& world = *bench->world;
  const std::size_t kMultimeter = 0;
  const ObjectClass& box = bench->catalog->get("materialbox");
  const Eigen::Isometry3d T_box =
      test::poseXyzYaw(bench->truth[kMultimeter].translation() +
                           Eigen::Vector3d(0.0, 0.12, 0.5 * box.box.sizes().z() - 0.022),
                       0.0);
  const NodeId occluder = 41;
  world.addInstance(occluder, world.addMesh(box.mesh), T_box);
  world.setInstanceEnabled(occluder, false);
  world.commit();
  PipelineOptions options;
  options.localize = false;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  const PinholeModel cam = PinholeModel::xtion();
  auto cam_rays = std::make_shared<SensorRays>(makeRays(cam));
  const int kRate = 15, kCovered = 15, kUncovered = 45;
  std::string occluder_track;
  double removed_at = -1.0;
  for (int f = 0; f <= 75 && removed_at < 0.0; ++f) {
    const double t = static_cast<double>(f) / kRate;
    if (f == kCovered) {  // the multimeter goes as the box is put in front of it
      world.setInstanceEnabled(test::BenchScene::objectNode(kMultimeter), false);
      world.setInstanceEnabled(occluder, true);
      world.commit();
      occluder_track = pipeline.addTrack("materialbox", T_box, t);
    }
    if (f == kUncovered) {
      world.setInstanceEnabled(occluder, false);
      world.commit();
      pipeline.removeTrack(occluder_track);
    }
    PipelineFrame frame;
    frame.stamp = t;
    frame.T_odom_base = bench->T_map_base;
    const SimulatedScan scan = simulate(world, *cam_rays, bench->T_map_base * bench->T_base_camera);
    frame.measurements.push_back(fromDepthImage(cam, cam_rays, depthImage(scan, *cam_rays),
                                                bench->T_map_base * bench->T_base_camera));
    addDepthNoise(frame.measurements.back(), 0.0015, 500 + f);
    for (std::size_t k = 0; k < bench->classes.size() && f < kCovered; ++k)
      frame.hypotheses.push_back(
          {bench->classes[k], bench->T_map_base.inverse() * bench->truth[k], 0.9});
    const PipelineResult r = pipeline.process(frame);
    if (f > kCovered && !findClass(r, "multimeter")) removed_at = t;
  }
  removed_after_covered = removed_at - static_cast<double>(kCovered) / kRate;
  return removed_at;
}

TEST(TrackLifecycle, GoneBehindATrackItIsRemovedByTheRaysThatStillReachIt) {
  double after_covered = 0.0;
  const double removed_at = removedWhileHiddenAt(after_covered);
  std::cout << "[ figures  ] multimeter gone behind a tracked box at 1.0 s, uncovered at 3.0 s: "
               "removed at "
            << removed_at << " s\n";
  ASSERT_GT(removed_at, 0.0) << "never removed";
  EXPECT_GT(after_covered, 0.5) << "removed too early: evidence of absence needs time";
  EXPECT_LE(after_covered, 1.2) << "the rays past the box should remove it within ~1 s";
}

}  // namespace
}  // namespace sgt
