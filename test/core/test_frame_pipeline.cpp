// The per-frame pipeline on a simulated sequence: a robot whose odometry is 20 cm / 3 deg off
// in front of the workbench with the five catalog objects, a box the catalog does not know, and
// noisy detections plus one false detection. The pipeline must correct the robot pose, refine
// the objects well below the detection noise, label the box's points unknown and drop the
// false detection.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

#include "scene_graph_tracker/evaluation/pose_metrics.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

TEST(FramePipeline, LocalizesRefinesSegmentsAndDropsAFalseDetection) {
  const auto bench = test::benchScene();
  const auto& [map, catalog, world_ptr, top, classes, truth, T_map_base, T_base_camera,
               T_base_lidar] = *bench;
  RaycastScene& world = *world_ptr;
  // An unknown box on the bench.
  const NodeId unknown_box = 30;
  world.addInstance(unknown_box,
                    world.addMesh(std::make_shared<TriangleMesh>(makeBox({0.12f, 0.1f, 0.15f}))),
                    test::poseXyzYaw(top + Eigen::Vector3d(-0.1, -0.25, 0.075), 0.0));
  world.commit();

  // Robot 1.1 m in front of the bench; odometry believes it is 20 cm / 3 deg elsewhere.
  const Eigen::Isometry3d T_map_odom_true =
      test::poseXyzYaw(Eigen::Vector3d(0.15, -0.13, 0.0), 3.0 * M_PI / 180.0);
  const Eigen::Isometry3d T_odom_base = T_map_odom_true.inverse() * T_map_base;
  const PinholeModel cam = PinholeModel::xtion();
  auto cam_rays = std::make_shared<SensorRays>(makeRays(cam));
  auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const SimulatedScan cam_scan = simulate(world, *cam_rays, T_map_base * T_base_camera);
  const SimulatedScan lidar_scan = simulate(world, *lidar_rays, T_map_base * T_base_lidar);

  FramePipeline pipeline(catalog, map);
  std::mt19937 rng(5);
  std::vector<std::string> dropped;
  std::normal_distribution<double> g;
  PipelineResult r;
  for (int f = 0; f < 12; ++f) {
    PipelineFrame frame;
    frame.stamp = f / 30.0;
    frame.T_odom_base = T_odom_base;
    frame.measurements.push_back(fromDepthImage(cam, cam_rays, depthImage(cam_scan, *cam_rays),
                                                T_odom_base * T_base_camera));
    addDepthNoise(frame.measurements.back(), 0.0015, 100 + f);
    if (f % 3 == 0) {  // LiDAR at a third of the camera rate
      frame.measurements.push_back(fromRanges(SpinningLidarModel::vlp16(), lidar_rays,
                                              lidar_scan.range, T_odom_base * T_base_lidar));
      addRangeNoise(frame.measurements.back(), 0.01, 200 + f);
    }
    // Detections with 1 cm / 3 deg noise, and a multimeter where there is none (first frame).
    for (std::size_t k = 0; k < classes.size(); ++k) {
      Eigen::Isometry3d T = truth[k];
      T.translation() += 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      T.linear() = Eigen::AngleAxisd(3.0 * M_PI / 180.0 * g(rng),
                                     Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()) *
                   T.linear();
      frame.hypotheses.push_back({classes[k], T_map_base.inverse() * T, 0.9});
    }
    if (f == 0)
      frame.hypotheses.push_back(
          {"multimeter",
           T_map_base.inverse() * test::poseXyzYaw(top + Eigen::Vector3d(0.2, 0.3, 0.3), 0), 0.8});
    r = pipeline.process(frame);
    dropped.insert(dropped.end(), r.dropped.begin(), r.dropped.end());
  }

  // The robot: corrected to well within the localization goal (2 cm / 0.5 deg).
  EXPECT_LT((r.T_map_base.translation() - T_map_base.translation()).norm(), 0.01);
  EXPECT_LT(Eigen::AngleAxisd(r.T_map_base.linear().transpose() * T_map_base.linear()).angle() *
                180 / M_PI,
            0.3);
  // The objects: one track per real object, ADD-S below the 1 cm detection noise. The generated
  // meshes are coarse boxes-and-cylinders, so 5 mm leaves room for their ambiguity.
  ASSERT_EQ(r.objects.size(), 5u) << "the false multimeter must have been dropped";
  EXPECT_EQ(dropped, std::vector<std::string>{"multimeter_2"});
  for (const TrackedObject& o : r.objects) {
    const auto k = static_cast<std::size_t>(
        std::find(classes.begin(), classes.end(), o.class_name) - classes.begin());
    ASSERT_LT(k, classes.size());
    const ObjectClass& c = catalog->get(o.class_name);
    const PoseErrors e =
        poseErrors(c, sampleSurface(*c.mesh, 300, 1).points, o.T_map_object, truth[k]);
    EXPECT_LT(e.add_s, 0.005) << o.id;
    EXPECT_EQ(o.quality.status, RefineStatus::kOk) << o.id;
  }
  // Pre-segmentation: the unknown box's camera pixels come out unknown.
  ASSERT_FALSE(r.presegmentation.empty());
  std::size_t box = 0, box_unknown = 0;
  for (std::size_t i = 0; i < cam_scan.node.size(); ++i)
    if (cam_scan.node[i] == unknown_box && r.measurements[0].valid(i))
      ++box, box_unknown += r.presegmentation[0].label[i] == PointLabel::kUnknown;
  ASSERT_GT(box, 500u);
  EXPECT_GT(static_cast<double>(box_unknown) / box, 0.95);
}

// A camera with a strong plumb_bob lens (unrectified depth): with its distortion in the model the
// objects refine onto the truth; taken as a plain pinhole, its corner rays point up to ~9 deg
// elsewhere and the objects end centimetres off.
double worstErrorWithLens(bool model_knows_the_lens) {
  const auto bench = test::benchScene();
  PinholeModel lens = PinholeModel::xtion();
  lens.distortion = {-0.28, 0.09, 0.0012, -0.0008, -0.01};
  PinholeModel cam = lens;
  if (!model_knows_the_lens) cam.distortion = {};
  const auto lens_rays = std::make_shared<SensorRays>(makeRays(lens));
  const auto cam_rays = std::make_shared<SensorRays>(makeRays(cam));
  const Eigen::Isometry3d T_map_camera = bench->T_map_base * bench->T_base_camera;
  const SimulatedScan scan = simulate(*bench->world, *lens_rays, T_map_camera);
  PipelineOptions options;
  options.localize = false;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  PipelineResult r;
  for (int f = 0; f < 6; ++f) {
    PipelineFrame frame;
    frame.stamp = f / 30.0;
    frame.T_odom_base = bench->T_map_base;
    frame.measurements.push_back(
        fromDepthImage(cam, cam_rays, depthImage(scan, *lens_rays), T_map_camera));
    for (std::size_t k = 0; k < bench->classes.size(); ++k) {
      Eigen::Isometry3d T = bench->truth[k];
      T.translation() += Eigen::Vector3d(0.008, -0.006, 0.004);
      frame.hypotheses.push_back({bench->classes[k], bench->T_map_base.inverse() * T, 0.9});
    }
    r = pipeline.process(frame);
  }
  double worst = 0.0;
  for (std::size_t k = 0; k < bench->classes.size(); ++k) {
    double best = 1e9;  // the track of this class nearest the truth
    for (const TrackedObject& o : r.objects)
      if (o.class_name == bench->classes[k])
        best =
            std::min(best, (o.T_map_object.translation() - bench->truth[k].translation()).norm());
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(FramePipeline, ADistortedCameraRefinesWithItsLensModel) {
  EXPECT_LT(worstErrorWithLens(true), 0.003);
  EXPECT_GT(worstErrorWithLens(false), 0.01);
}

TEST(FramePipeline, EmptyFramesKeepItRunning) {
  auto catalog = std::make_shared<ObjectCatalog>(
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml"));
  FramePipeline pipeline(catalog, std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})));
  PipelineFrame empty;
  const PipelineResult r = pipeline.process(empty);
  EXPECT_TRUE(r.objects.empty());
  EXPECT_FALSE(r.localized);
  PipelineFrame unknown_class;
  unknown_class.hypotheses.push_back({"teapot", Eigen::Isometry3d::Identity(), 1.0});
  EXPECT_TRUE(pipeline.process(unknown_class).objects.empty());
}

// T turned by 90 deg about its own z axis.
Eigen::Isometry3d quarterTurned(Eigen::Isometry3d T) {
  return T.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
}

// The bench with one unknown thing added (node 30), as the standing robot's camera sees it; a
// frame of that view at 30 Hz with fresh depth noise.
struct UnknownThingView {
  std::unique_ptr<test::BenchScene> bench;
  PinholeModel cam = PinholeModel::xtion();
  std::shared_ptr<SensorRays> rays;
  SimulatedScan scan;
  static constexpr NodeId kThing = 30;
  UnknownThingView(TriangleMesh thing, const Eigen::Isometry3d& T_map_thing) {
    bench = test::benchScene();
    bench->world->addInstance(
        kThing, bench->world->addMesh(std::make_shared<TriangleMesh>(std::move(thing))),
        T_map_thing);
    bench->world->commit();
    rays = std::make_shared<SensorRays>(makeRays(cam));
    scan = simulate(*bench->world, *rays, bench->T_map_base * bench->T_base_camera);
  }
  PipelineFrame frame(int f, unsigned noise_seed) const {
    return test::depthFrame(f, bench->T_map_base, cam, rays, scan,
                            bench->T_map_base * bench->T_base_camera, 0.0015, noise_seed + f);
  }
};

// One false detection of a material box on an unknown carton of about its size (the demo's
// cardboard box): refinement alone fits it well, but a track needs more than one detection to
// be confirmed, so it never is and goes after tentative_timeout; a tentative track explains no
// points, so the carton stays unknown in every frame.
TEST(FramePipeline, OneFalseDetectionOnAnUnknownBoxIsNeitherConfirmedNorHidesIt) {
  const Eigen::Vector3d top = test::benchScene()->top;
  const Eigen::Isometry3d T_carton =
      test::poseXyzYaw(top + Eigen::Vector3d(-0.1, -0.25, 0.045), 0.1);
  const UnknownThingView view(makeBox({0.17f, 0.125f, 0.09f}), T_carton);
  const NodeId carton = UnknownThingView::kThing;
  const SimulatedScan& scan = view.scan;
  const Eigen::Isometry3d& T_map_base = view.bench->T_map_base;
  PipelineOptions options;
  options.localize = false;
  FramePipeline pipeline(view.bench->catalog, view.bench->map, options);
  std::size_t carton_pixels = 0, worst_unknown = ~std::size_t{0};
  bool confirmed = false, present_at_end = false;
  for (int f = 0; f < 45; ++f) {  // 1.5 s at 30 Hz
    PipelineFrame frame = view.frame(f, 400);
    if (f == 0) frame.hypotheses.push_back({"materialbox", T_map_base.inverse() * T_carton, 0.9});
    const PipelineResult r = pipeline.process(frame);
    present_at_end = false;
    for (const TrackedObject& o : r.objects)
      if (o.class_name == "materialbox")
        confirmed |= o.state != TrackState::kTentative, present_at_end = true;
    std::size_t pixels = 0, unknown = 0;
    for (std::size_t i = 0; i < scan.node.size(); ++i)
      if (scan.node[i] == carton && r.measurements[0].valid(i))
        ++pixels, unknown += r.presegmentation[0].label[i] == PointLabel::kUnknown;
    carton_pixels = pixels;
    worst_unknown = std::min(worst_unknown, unknown * 100 / std::max<std::size_t>(pixels, 1));
  }
  ASSERT_GT(carton_pixels, 500u);
  EXPECT_FALSE(confirmed);
  EXPECT_FALSE(present_at_end) << "the tentative track outlives tentative_timeout";
  EXPECT_GE(worst_unknown, 95u) << "% of the carton's pixels labelled unknown in the worst frame";
}

// A detector that keeps detecting a KLT on a thin unknown thing (a post behind the bench, 14 cm
// wide: narrower than the crate's smallest side, 14.7 cm, so no turn of the crate fits inside
// it): every detection associates with the track at the detection, and refinement fits the
// crate to the post's front, but that fit leaves a large share of the rays reaching the model
// unexplained (the crate's sides see past the post), so it is never confirmed. (A second track,
// which refinement slides down onto the bench edge against the post, explains about 70 % there
// and may be confirmed: this rule only judges fits.) A post as wide as the crate's standing face
// is no test: the refiner rolls the crate on end against it, where it explains 65-76 %.
struct PostScene {
  static constexpr float kPostRadius = 0.07f;
  Eigen::Vector3d feet = test::benchScene()->top + Eigen::Vector3d(-0.25, -0.75, -0.75);
  Eigen::Isometry3d T_post = test::poseXyzYaw(feet + Eigen::Vector3d(0, 0, 0.875), 0.0);
  // The crate stuck in the post with its front face on the post's front, over the bench.
  Eigen::Isometry3d T_false =
      test::poseXyzYaw(feet + Eigen::Vector3d(0, kPostRadius - 0.099, 1.0), 0.0);
  // A ball of 20 cm radius held 10 cm above the bench, and the crate with its front face
  // touching the ball's front.
  Eigen::Isometry3d T_ball = test::poseXyzYaw(feet + Eigen::Vector3d(0, 0, 1.05), 0.0);
  Eigen::Isometry3d T_on_ball = test::poseXyzYaw(feet + Eigen::Vector3d(0, 0.2 - 0.099, 1.05), 0.0);
};

// Whether a track within 10 cm of the detection was confirmed.
bool falseDetectionsOnAPostConfirmed(double confirm_inlier_ratio, double min_fit_support) {
  const PostScene post;
  const UnknownThingView view(makeCylinder(PostScene::kPostRadius, 1.75f), post.T_post);
  PipelineOptions options;
  options.localize = false;
  options.confirm_inlier_ratio = confirm_inlier_ratio;
  options.min_fit_support = min_fit_support;
  FramePipeline pipeline(view.bench->catalog, view.bench->map, options);
  bool confirmed = false;
  for (int f = 0; f < 30; ++f) {
    PipelineFrame frame = view.frame(f, 700);
    frame.hypotheses.push_back({"klt", view.bench->T_map_base.inverse() * post.T_false, 0.9});
    for (const TrackedObject& o : pipeline.process(frame).objects)
      confirmed |= o.class_name == "klt" && o.state != TrackState::kTentative &&
                   (o.T_map_object.translation() - post.T_false.translation()).norm() < 0.1;
  }
  return confirmed;
}

TEST(FramePipeline, RepeatedFalseDetectionsOnAPostAreNotConfirmed) {
  const PipelineOptions defaults;
  EXPECT_FALSE(
      falseDetectionsOnAPostConfirmed(defaults.confirm_inlier_ratio, defaults.min_fit_support));
  // Confirmation by detections and any fit (the rule before): confirmed.
  EXPECT_TRUE(falseDetectionsOnAPostConfirmed(0.0, 0.0))
      << "the scene must make the crate fit the post (else no test)";
}

// A real KLT, held up, is confirmed; then it is gone and the unknown post stands there, while
// the detector goes on reporting a KLT (as on the demo's walking person). The confirmed track's
// fits to the post (a ball) leave half its rays unexplained, whether the track takes them or the
// turn gate keeps its pose (the refiner may turn the crate farther than the motion model allows):
// its fit support falls below min_fit_support, it stops explaining the post's points and is
// removed after remove_after_s.
// With min_fit_support 0 it stays and hides the post. Returns the share (%) of the post's points
// labelled unknown in the last frame, and whether a KLT track was left.
std::pair<std::size_t, bool> confirmedTrackOnAPostAfterTheCrateLeft(double min_fit_support) {
  const PostScene post;
  const auto crate = test::benchScene()->catalog->get("klt").mesh;
  const UnknownThingView with_crate(*crate, post.T_on_ball);
  const UnknownThingView with_post(makeSphere(0.2f), post.T_ball);
  PipelineOptions options;
  options.localize = false;
  options.min_fit_support = min_fit_support;
  FramePipeline pipeline(with_post.bench->catalog, with_post.bench->map, options);
  std::size_t unknown_share = 0;
  bool crate_left = false;
  for (int f = 0; f < 90; ++f) {  // the crate for 0.5 s, then the post for 2.5 s
    const UnknownThingView& view = f < 15 ? with_crate : with_post;
    PipelineFrame frame = view.frame(f, 900);
    frame.hypotheses.push_back({"klt", view.bench->T_map_base.inverse() * post.T_on_ball, 0.9});
    const PipelineResult r = pipeline.process(frame);
    crate_left = false;
    for (const TrackedObject& o : r.objects)
      crate_left |= o.class_name == "klt" && o.state != TrackState::kTentative;
    if (f == 14) {
      EXPECT_TRUE(crate_left) << "the real crate is confirmed";
    }
    std::size_t pixels = 0, unknown = 0;
    for (std::size_t i = 0; i < view.scan.node.size(); ++i)
      if (view.scan.node[i] == UnknownThingView::kThing && r.measurements[0].valid(i))
        ++pixels, unknown += r.presegmentation[0].label[i] == PointLabel::kUnknown;
    unknown_share = unknown * 100 / std::max<std::size_t>(pixels, 1);
  }
  return {unknown_share, crate_left};
}

TEST(FramePipeline, AConfirmedTrackTheMeasurementsContradictGoes) {
  const auto [unknown, left] =
      confirmedTrackOnAPostAfterTheCrateLeft(PipelineOptions().min_fit_support);
  EXPECT_FALSE(left);
  EXPECT_GE(unknown, 95u) << "% of the post's points labelled unknown at the end";
  const auto [unknown_before, left_before] = confirmedTrackOnAPostAfterTheCrateLeft(0.0);
  EXPECT_TRUE(left_before) << "without the rule the track must stay on the post (else no test)";
  EXPECT_LT(unknown_before, 90u);
}

// A multimeter held above the KLT is confirmed; then it is let go into the KLT, where the
// crate's walls hide it from the camera, and the detector sees it no more. Where its track
// coasts, the camera sees through it: with unseen_drop_m the track drops onto the crate's floor,
// where nothing shows it missing, and stays; without, that evidence of absence removes it after
// remove_after_s. Returns the multimeter track's error at the end (m; infinity when it has gone)
// and whether the crate really hides it (else no test).
std::pair<double, bool> multimeterLetGoIntoTheKlt(double unseen_drop_m) {
  const auto bench = test::benchScene();
  const auto index = [&](const std::string& c) {
    return std::find(bench->classes.begin(), bench->classes.end(), c) - bench->classes.begin();
  };
  const std::size_t klt = index("klt"), meter = index("multimeter");
  RaycastScene& world = *bench->world;
  // The crate's floor under its centre: a ray straight down from above the crate.
  const Eigen::Vector3d centre = bench->truth[klt].translation();
  RayHits floor_hit;
  world.cast({{Eigen::Vector3f(centre.x(), centre.y(), centre.z() + 1.0), -Eigen::Vector3f::UnitZ(),
               2.0f}},
             floor_hit);
  const double box_bottom = bench->catalog->get("multimeter").box.min().z();
  Eigen::Isometry3d T_in = bench->truth[meter], T_above = bench->truth[meter];
  T_in.translation() = Eigen::Vector3d(centre.x(), centre.y(), floor_hit.point[0].z() - box_bottom);
  T_above.translation() = T_in.translation() + Eigen::Vector3d(0.0, 0.0, 0.3);
  const auto [T_map_base, T_map_camera] = test::facingTheBench(*bench, 2.0);
  const PinholeModel cam = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  std::vector<SimulatedScan> scans;
  for (const Eigen::Isometry3d& T : {T_above, T_in}) {
    world.setInstancePose(test::BenchScene::objectNode(meter), T);
    world.commit();
    scans.push_back(simulate(world, *rays, T_map_camera));
  }
  const bool hidden = std::none_of(scans[1].node.begin(), scans[1].node.end(), [&](NodeId n) {
    return n == test::BenchScene::objectNode(meter);
  });
  PipelineOptions options;
  options.localize = false;
  options.unseen_drop_m = unseen_drop_m;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  double error = std::numeric_limits<double>::infinity();
  for (int f = 0; f < 90; ++f) {  // held above for 1 s, then in the crate for 2 s
    PipelineFrame frame = test::depthFrame(f, T_map_base, cam, rays, scans[f < 30 ? 0 : 1],
                                           T_map_camera, 0.0015, 300 + f);
    frame.hypotheses.push_back({"klt", T_map_base.inverse() * bench->truth[klt], 0.9});
    if (f < 30) frame.hypotheses.push_back({"multimeter", T_map_base.inverse() * T_above, 0.9});
    error = std::numeric_limits<double>::infinity();
    for (const TrackedObject& o : pipeline.process(frame).objects)
      if (o.class_name == "multimeter" && o.state != TrackState::kTentative)
        error = (o.T_map_object.translation() - T_in.translation()).norm();
  }
  return {error, hidden};
}

TEST(FramePipeline, ATrackSeenMissingWhereItHoversDropsOutOfSightAndStays) {
  const auto [error, hidden] = multimeterLetGoIntoTheKlt(PipelineOptions().unseen_drop_m);
  ASSERT_TRUE(hidden) << "the crate must hide the multimeter (else no test)";
  EXPECT_LT(error, 0.02) << "m, the track in the crate";
  EXPECT_EQ(multimeterLetGoIntoTheKlt(0.0).first, std::numeric_limits<double>::infinity())
      << "without the drop the track must go (else no test)";
}

// A multimeter carried 0.35 m above the bench is confirmed; then it is put down and the camera,
// come closer, looks down at the bench, so the place where its track hovers is out of view (no
// ray reaches it). With unseen_drop_m beyond the lift, the track drops onto the bench under it,
// where the multimeter lies; without, it hovers on. When the detector sees the multimeter on the
// bench (detected_down, from 1/3 s after the put-down on), those detections lie 0.35 m from a
// track that no ray has reached for ten frames. Returns where the confirmed multimeter tracks end
// and whether the second view leaves the hover place out and shows the multimeter (else no test).
struct PutDown {
  std::vector<Eigen::Vector3d> tracks;
  bool valid = false;
  Eigen::Vector3d up, down;
};

PutDown multimeterPutDownOutOfItsTracksView(double unseen_drop_m, bool detected_down) {
  const auto bench = test::benchScene();
  const std::size_t meter = std::find(bench->classes.begin(), bench->classes.end(), "multimeter") -
                            bench->classes.begin();
  RaycastScene& world = *bench->world;
  const Eigen::Isometry3d T_down = bench->truth[meter];
  Eigen::Isometry3d T_up = T_down;
  T_up.translation().z() += 0.35;
  const auto [T_map_base, T_far] = test::facingTheBench(*bench, 2.0);
  const Eigen::Isometry3d T_near =
      opticalLookAt(T_down.translation() + Eigen::Vector3d(0.0, 0.5, 0.5),
                    T_down.translation() + Eigen::Vector3d(0.0, 0.15, 0.0));
  const PinholeModel cam = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  std::vector<SimulatedScan> scans;
  for (const auto& [T_object, T_camera] : {std::pair{T_up, T_far}, std::pair{T_down, T_near}}) {
    world.setInstancePose(test::BenchScene::objectNode(meter), T_object);
    world.commit();
    scans.push_back(simulate(world, *rays, T_camera));
  }
  const Eigen::Isometry3d T_camera_up = T_near.inverse() * T_up;
  const auto inImage = [&](const Eigen::Vector3d& p) {
    const auto uv = cam.project(p);
    return uv && uv->x() >= 0 && uv->y() >= 0 && uv->x() < cam.width && uv->y() < cam.height;
  };
  PutDown out;
  out.up = T_up.translation(), out.down = T_down.translation();
  out.valid = std::any_of(scans[1].node.begin(), scans[1].node.end(),
                          [&](NodeId n) { return n == test::BenchScene::objectNode(meter); });
  const Eigen::AlignedBox3d box = bench->catalog->get("multimeter").box.cast<double>();
  for (int c = 0; c < 8; ++c)
    out.valid = out.valid &&
                !inImage(T_camera_up * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  PipelineOptions options;
  options.localize = false;
  options.unseen_drop_m = unseen_drop_m;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  for (int f = 0; f < 75; ++f) {  // carried for 1 s, then put down and seen from near for 1.5 s
    const bool up = f < 30;
    PipelineFrame frame = test::depthFrame(f, T_map_base, cam, rays, scans[up ? 0 : 1],
                                           up ? T_far : T_near, 0.0015, 500 + f);
    if (up || (detected_down && f >= 40))  // down: once no ray has reached the track
      frame.hypotheses.push_back({"multimeter", T_map_base.inverse() * (up ? T_up : T_down), 0.9});
    out.tracks.clear();
    for (const TrackedObject& o : pipeline.process(frame).objects)
      if (o.class_name == "multimeter" && o.state != TrackState::kTentative)
        out.tracks.push_back(o.T_map_object.translation());
  }
  return out;
}

std::pair<double, bool> multimeterPutDownOutOfItsTracksView(double unseen_drop_m) {
  const PutDown p = multimeterPutDownOutOfItsTracksView(unseen_drop_m, false);
  if (p.tracks.size() != 1) return {std::numeric_limits<double>::infinity(), p.valid};
  return {(p.tracks[0] - p.down).norm(), p.valid};
}

TEST(FramePipeline, ATrackHoveringOutOfViewDropsOntoWhatLiesBelow) {
  const auto [error, valid] = multimeterPutDownOutOfItsTracksView(PipelineOptions().unseen_drop_m);
  ASSERT_TRUE(valid) << "the near view must leave the hover place out and show the multimeter";
  EXPECT_LT(error, 0.02) << "m, the track on the bench";
  const double hovering = multimeterPutDownOutOfItsTracksView(0.0).first;
  EXPECT_GT(hovering, 0.3) << "without the drop the track must hover on (else no test)";
  EXPECT_LT(hovering, 0.4);
}

// The detector sees a multimeter on the bench 0.35 m from a confirmed track that no ray reaches
// (out of view) and that was never seen missing: within reacquire_distance, yet nothing says the
// track's object left its place, so the detection is another object and starts its own track.
TEST(FramePipeline, ADetectionAwayFromATrackNoRayReachesStartsAnotherTrack) {
  const PutDown p = multimeterPutDownOutOfItsTracksView(0.0, true);
  ASSERT_TRUE(p.valid) << "the near view must leave the hover place out and show the multimeter";
  ASSERT_LT(0.35, PipelineOptions().reacquire_distance) << "else no test";
  ASSERT_EQ(p.tracks.size(), 2u);
  const auto near = [&](const Eigen::Vector3d& where) {
    return std::count_if(p.tracks.begin(), p.tracks.end(),
                         [&](const Eigen::Vector3d& t) { return (t - where).norm() < 0.02; });
  };
  EXPECT_EQ(near(p.up), 1) << "the unseen track stays where it was last seen";
  EXPECT_EQ(near(p.down), 1) << "the detection's object gets a track of its own";
}

// A detector keeps reporting a relay on the floor behind the robot, out of the camera's view, so
// no ray can tell whether it is there. Resting on the floor, its track stays;
// sunk 4 cm into the floor it is nowhere a real object can be and goes after
// remove_tentative_after_s each time (the next detection starts a new one), unless the rule is
// off (max_sunk_fraction 1). Returns the longest life of a relay track over 2 s.
double longestRelayTrackBehindTheRobot(double z_offset, double max_sunk_fraction) {
  const Eigen::Vector3d top = test::benchScene()->top;
  const UnknownThingView view(makeBox({0.05f, 0.05f, 0.05f}),
                              test::poseXyzYaw(top + Eigen::Vector3d(0, 0, 0.3), 0.0));
  PipelineOptions options;
  options.localize = false;
  options.max_sunk_fraction = max_sunk_fraction;
  FramePipeline pipeline(view.bench->catalog, view.bench->map, options);
  const double half_height = 0.104 / 2;
  Eigen::Vector3d behind = view.bench->T_map_base * Eigen::Vector3d(-1.0, 0.0, 0.0);
  behind.z() = top.z() - 0.75 + half_height + z_offset;
  const Eigen::Isometry3d T_relay = test::poseXyzYaw(behind, 0.3);
  double longest = 0.0;
  for (int f = 0; f < 60; ++f) {
    PipelineFrame frame = view.frame(f, 1100);
    frame.hypotheses.push_back({"relay", view.bench->T_map_base.inverse() * T_relay, 0.9});
    const PipelineResult r = pipeline.process(frame);
    for (const TrackedObject& o : r.objects) {
      if (o.class_name != "relay") continue;
      EXPECT_EQ(o.quality.status, RefineStatus::kNotVisible)
          << "it must be out of view (else no test)";
      longest = std::max(longest, r.stamp - o.first_seen);
    }
  }
  return longest;
}

TEST(FramePipeline, ATrackSunkIntoTheMapGoesEvenUnseen) {
  const double defaults = PipelineOptions().max_sunk_fraction;
  EXPECT_GT(longestRelayTrackBehindTheRobot(0.001, defaults), 1.9) << "resting on the floor";
  EXPECT_LT(longestRelayTrackBehindTheRobot(-0.04, defaults), 0.5) << "4 cm into the floor";
  EXPECT_GT(longestRelayTrackBehindTheRobot(-0.04, 1.0), 1.9) << "without the rule";
}

// The screwdriver seen from 2.8 m by a QVGA depth camera: its fits have 5-8 inliers, fewer than
// the alignment's min_points, and the detector places it 4 cm off along its axis in every frame
// (the detector demo's start: 7-15 cm off, 5-15 rays at VGA). Its tentative track's weak fits
// (min_weak_fit_inliers) place it, and the next frame refines from there rather than from the
// detection. Depth noise 4 mm at that range (0.5 mm at 1 m), a third of the demo's: at 12 mm
// single fits of 5-10 points scatter by centimetres (the demo's recall gain is statistical).
// Returns the track's mean translation error over the last 0.5 s of 1.5 s.
double farScrewdriverError(int min_weak_fit_inliers, int* fewest_inliers) {
  const auto bench = test::benchScene();
  const auto [T_map_base, T_camera] = test::facingTheBench(*bench, 2.8);
  const PinholeModel cam = test::qvgaCam();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const SimulatedScan scan = simulate(*bench->world, *rays, T_camera);
  const Eigen::Isometry3d& truth = bench->truth[1];  // the screwdriver; its axis is x
  Eigen::Isometry3d detected = truth;
  detected.translation() += 0.04 * truth.linear().col(0);
  PipelineOptions options;
  options.localize = false;
  options.min_weak_fit_inliers = min_weak_fit_inliers;
  FramePipeline pipeline(bench->catalog, bench->map, options);
  double error = 0.0;
  int counted = 0;
  *fewest_inliers = 1 << 30;
  for (int f = 0; f < 45; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, T_map_base, cam, rays, scan, T_camera, 0.0005, 1300 + f);
    frame.hypotheses.push_back({"screwdriver", T_map_base.inverse() * detected, 0.9});
    const PipelineResult r = pipeline.process(frame);
    for (const TrackedObject& o : r.objects) {
      if (o.class_name != "screwdriver") continue;
      *fewest_inliers = std::min(*fewest_inliers, o.quality.inliers);
      if (f >= 30) error += (o.T_map_object.translation() - truth.translation()).norm(), ++counted;
    }
  }
  return counted > 0 ? error / counted : 1.0;
}

TEST(FramePipeline, AFarSmallObjectsWeakFitsPlaceItsTentativeTrack) {
  int fewest = 0;
  const double with_rule = farScrewdriverError(PipelineOptions().min_weak_fit_inliers, &fewest);
  EXPECT_LT(fewest, PipelineOptions().refiner.alignment.min_points)
      << "its fits must be weak (else no test)";
  const double without = farScrewdriverError(1 << 20, &fewest);
  std::printf("far screwdriver: %.1f mm with the rule, %.1f mm without\n", 1000 * with_rule,
              1000 * without);
  // The detections fused into the filter (fuse_hypotheses) pull it part of the way back.
  EXPECT_LT(with_rule, 0.02) << "m, mean, last 0.5 s";
  EXPECT_GT(without, 0.03) << "m: without the rule it stays at the detection";
}

// The material box is detected turned by 90 deg about z in every frame. For 2 s the robot is
// 2.8 m away with a QVGA depth image: the track is confirmed (thresholds lowered for that) at
// the detection's turn. Then from 1.1 m (VGA) the turned model explains 89 % of its rays, below
// research_below_fit_support: searched again, it turns right. Without the rule it keeps the turn
// to the end (as the demo's material box with scenario seed 44 did). Returns the track's
// rotation error at the end (deg).
double turnedMaterialBoxErrorDeg(double research_below_fit_support) {
  const auto bench = test::benchScene();
  const Eigen::Isometry3d& truth = bench->truth[2];  // the material box
  const Eigen::Isometry3d turned = quarterTurned(truth);
  const PinholeModel cam = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const PinholeModel far_cam = test::qvgaCam();
  const auto far_rays = std::make_shared<SensorRays>(makeRays(far_cam));
  struct View {
    const PinholeModel* cam;
    std::shared_ptr<SensorRays> rays;
    Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity(),
                      T_camera = Eigen::Isometry3d::Identity();
    SimulatedScan scan = {};
  };
  std::vector<View> views{{&far_cam, far_rays}, {&cam, rays}};  // from 2.8 m, then from 1.1 m
  for (View& v : views) {
    std::tie(v.T_map_base, v.T_camera) =
        test::facingTheBench(*bench, v.cam == &far_cam ? 2.8 : 1.1);
    v.scan = simulate(*bench->world, *v.rays, v.T_camera);
  }
  PipelineOptions options;
  options.localize = false;
  // The keypoint detector's configuration (evaluate --detector): its detections, turned here,
  // neither dispute nor replace a track's turn.
  options.search_orientations = true;
  options.orientation_disputes = 0;
  options.restart_replaces_outliers = false;
  options.research_below_fit_support = research_below_fit_support;
  options.confirm_inlier_ratio = options.min_fit_support = 0.4;  // confirmed far away, turned
  // Far away the track takes the detections' turn: no search there (whether one from 2.8 m finds
  // the right turn is a toss-up that differs between CPUs).
  PipelineOptions far = options;
  far.search_orientations = false;
  FramePipeline pipeline(bench->catalog, bench->map, far);
  double error = 180.0;
  for (int f = 0; f < 150; ++f) {
    if (f == 60) pipeline.setOptions(options);
    const View& v = views[f < 60 ? 0 : 1];
    PipelineFrame frame;
    frame.stamp = f / 30.0;
    frame.T_odom_base = v.T_map_base;
    frame.measurements.push_back(
        fromDepthImage(*v.cam, v.rays, depthImage(v.scan, *v.rays), v.T_camera));
    addDepthNoise(frame.measurements.back(), 0.0015, 1500 + f);
    frame.hypotheses.push_back({"materialbox", v.T_map_base.inverse() * turned, 0.9});
    const PipelineResult r = pipeline.process(frame);
    for (const TrackedObject& o : r.objects)
      if (o.class_name == "materialbox") {
        error = test::rotationErrorDeg(o.T_map_object.linear(), truth.linear());
      }
  }
  return error;
}

TEST(FramePipeline, AConfirmedTrackThatExplainsTooLittleIsSearchedAgain) {
  EXPECT_LT(turnedMaterialBoxErrorDeg(PipelineOptions().research_below_fit_support), 5.0);
  EXPECT_GT(turnedMaterialBoxErrorDeg(0.0), 45.0)
      << "without the rule it must keep the turn (else no test)";
}

// The material box's track is confirmed turned by 90 deg (its first detections were), and the
// turned model fits well enough to refine on (no re-search: research_below_fit_support 0). Then
// the detections see it as it is: they dispute the track's orientation, the depth supports them,
// and the track ends where one detected right from the start ends (the refinement keeps a few
// degrees of error on this view either way). Without disputes it keeps the turn. Returns the
// final error (deg).
double disputedMaterialBoxErrorDeg(int orientation_disputes, int turned_frames = 60) {
  const test::StandingView v = test::standingView(1.1);
  const auto& [bench, cam, rays, T_map_base, T_camera, scan] = v;
  const Eigen::Isometry3d& truth = bench->truth[2];  // the material box
  const Eigen::Isometry3d turned = quarterTurned(truth);
  PipelineOptions options;
  options.localize = false;
  options.research_below_fit_support = 0.0;
  options.orientation_disputes = orientation_disputes;
  options.confirm_inlier_ratio = options.min_fit_support = 0.4;  // confirmed turned
  FramePipeline pipeline(bench->catalog, bench->map, options);
  double error = 180.0;
  for (int f = 0; f < 120; ++f) {
    PipelineFrame frame =
        test::depthFrame(f, T_map_base, cam, rays, scan, T_camera, 0.0015, 2500 + f);
    frame.hypotheses.push_back(
        {"materialbox", T_map_base.inverse() * (f < turned_frames ? turned : truth), 0.9});
    for (const TrackedObject& o : pipeline.process(frame).objects)
      if (o.class_name == "materialbox")
        error = test::rotationErrorDeg(o.T_map_object.linear(), truth.linear());
  }
  return error;
}

TEST(FramePipeline, DetectionsThatDisputeATracksTurnGetItRightWhenTheDepthAgrees) {
  const int disputes = PipelineOptions().orientation_disputes;
  EXPECT_NEAR(disputedMaterialBoxErrorDeg(disputes), disputedMaterialBoxErrorDeg(disputes, 0), 2.0);
  EXPECT_GT(disputedMaterialBoxErrorDeg(0), 45.0)
      << "without disputes it must keep the turn (else no test)";
}

// A robot driving past the bench with drifting odometry: every LiDAR frame corrects map -> odom.
// Composing `estimate * prior.inverse() * map_odom` with Isometry3d::inverse() (a transpose)
// amplified any deviation from a rotation about threefold per correction, until the scans were
// sheared by half a percent after ~30 corrections and the localizer drifted off (issue 5). The
// correction must stay a rotation, and the robot must stay localized over many corrections.
TEST(FramePipeline, ManyCorrectionsKeepMapToOdomRigidAndTheRobotLocalized) {
  const auto bench = test::benchScene();
  const auto& [map, catalog, world_ptr, top, classes, truth, T_map_base0, T_base_camera,
               T_base_lidar] = *bench;
  auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  PipelineOptions options;
  options.run_presegmentation = false;
  FramePipeline pipeline(catalog, map, options);
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  Eigen::Isometry3d T_odom_base = T_map_base0;  // odometry starts right and then drifts
  Eigen::Isometry3d T_map_base = T_map_base0;
  double worst_orthonormality = 0.0, worst_error = 0.0;
  int localized = 0;
  const int frames = 60;
  for (int f = 0; f < frames; ++f) {
    // True motion: 1 cm back and 0.3 deg per frame; odometry adds 1 mm and 0.5 mrad of noise.
    const Eigen::Isometry3d step =
        test::poseXyzYaw(Eigen::Vector3d(-0.01, 0.0, 0.0), 0.3 * M_PI / 180.0);
    T_map_base = T_map_base * step;
    T_odom_base = T_odom_base * step *
                  test::poseXyzYaw(0.001 * Eigen::Vector3d(g(rng), g(rng), 0.0), 0.0005 * g(rng));
    PipelineFrame frame;
    frame.stamp = f / 10.0;
    frame.T_odom_base = T_odom_base;
    const SimulatedScan scan = simulate(*world_ptr, *lidar_rays, T_map_base * T_base_lidar);
    frame.measurements.push_back(fromRanges(SpinningLidarModel::vlp16(), lidar_rays, scan.range,
                                            T_odom_base * T_base_lidar));
    addRangeNoise(frame.measurements.back(), 0.008, 300 + f);
    const PipelineResult r = pipeline.process(frame);
    localized += r.localized;
    worst_orthonormality = std::max(worst_orthonormality, orthonormalityError(r.T_map_odom));
    if (f >= 5)
      worst_error =
          std::max(worst_error, (r.T_map_base.translation() - T_map_base.translation()).norm());
  }
  EXPECT_LT(worst_orthonormality, 1e-9);
  EXPECT_EQ(localized, frames);
  EXPECT_LT(worst_error, 0.005);
}

}  // namespace
}  // namespace sgt

namespace sgt {
namespace {

TEST(FramePipeline, AFloodOfHypothesesIsBoundedAndCounted) {
  auto catalog = std::make_shared<ObjectCatalog>(
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml"));
  PipelineOptions options;
  options.max_hypotheses_per_frame = 30, options.max_tracks = 20, options.max_tracks_per_class = 8;
  FramePipeline pipeline(catalog, std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})), options);
  PipelineFrame flood;
  const std::vector<std::string> classes = catalog->names();
  for (int i = 0; i < 10000; ++i) {  // 1 m apart: no two associate
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(i % 100, i / 100, 0.0);
    flood.hypotheses.push_back({classes[i % classes.size()], T, 0.5 + 0.4 * i / 10000.0});
  }
  const PipelineResult r = pipeline.process(flood);
  EXPECT_LE(r.objects.size(), 20u);
  std::map<std::string, int> per_class;
  for (const TrackedObject& o : r.objects) {
    EXPECT_LE(++per_class[o.class_name], 8) << o.class_name;
    EXPECT_GE(o.T_map_object.translation().y(), 99.0);  // from the best-scored (the last) ones
  }
  EXPECT_EQ(r.hypotheses_over_limits, 10000u - r.objects.size());  // nothing silently lost
}

}  // namespace
}  // namespace sgt
