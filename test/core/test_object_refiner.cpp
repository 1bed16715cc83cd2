// Object refinement against ground truth from the project's own sensor simulation plus depth
// noise (sigma 1.5 mm at 1 m, growing with z^2): one object, five objects occluding each other,
// a false hypothesis, a symmetric object, no points / all-NaN depth.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/registration/object_refiner.hpp"
#include "scene_graph_tracker/registration/ray_regions.hpp"
#include "scene_graph_tracker/registration/unexplained_pairs.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

const ObjectCatalog& catalog() {
  static const ObjectCatalog c =
      loadObjectCatalog(std::string(SGT_SOURCE_DIR) + "/config/objects.yaml");
  return c;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& t, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(t);
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

// A perturbation of exactly the given magnitudes in random directions.
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T, double trans_m, double rot_deg,
                          std::mt19937& rng) {
  std::normal_distribution<double> g;
  const Eigen::Vector3d dt = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized() * trans_m;
  const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  Eigen::Isometry3d out = T;
  out.translation() += dt;
  out.linear() = Eigen::AngleAxisd(rot_deg * M_PI / 180.0, axis).toRotationMatrix() * T.linear();
  return out;
}

// A table top (z = 0.75) in a room, a camera 1 m away looking at it from above.
struct Bench {
  RaycastScene scene;
  PinholeModel camera = PinholeModel::xtion();
  std::shared_ptr<const SensorRays> rays = std::make_shared<SensorRays>(makeRays(camera));
  Eigen::Isometry3d T_world_camera = opticalLookAt({0.0, 0.8, 1.35}, {0.0, 0.0, 0.75});
  std::vector<std::pair<NodeId, Eigen::Isometry3d>> truth;
  std::vector<RefineTarget> targets;

  Bench() {
    TriangleMesh map = makeBox({1.6f, 0.8f, 0.04f});
    map.transform(Eigen::Isometry3f(Eigen::Translation3f(0, 0, 0.73f)));
    TriangleMesh wall = makeBox({4.0f, 0.1f, 3.0f});
    wall.transform(Eigen::Isometry3f(Eigen::Translation3f(0, -1.0f, 1.5f)));
    map.append(wall);
    scene.setStaticMap(std::make_shared<TriangleMesh>(map), 1);
  }
  // Places an object of `cls` resting on the table at (x, y) with yaw.
  NodeId add(const std::string& cls, double x, double y, double yaw, NodeId node) {
    const ObjectClass& c = catalog().get(cls);
    const MeshId mesh = scene.addMesh(c.mesh);
    const Eigen::Isometry3d T = pose({x, y, 0.75 - c.box.min().z()}, yaw);
    scene.addInstance(node, mesh, T);
    truth.emplace_back(node, T);
    targets.push_back({node, &c.symmetry});
    return node;
  }
  RangeMeasurements measure(std::uint32_t seed) {
    scene.commit();
    const SimulatedScan scan = simulate(scene, *rays, T_world_camera);
    RangeMeasurements m = fromDepthImage(camera, rays, depthImage(scan, *rays), T_world_camera);
    addDepthNoise(m, 0.0015, seed);
    return m;
  }
  void perturbAll(double trans_m, double rot_deg, std::uint32_t seed) {
    std::mt19937 rng(seed);
    for (const auto& [node, T] : truth)
      scene.setInstancePose(node, perturb(T, trans_m, rot_deg, rng));
    scene.commit();
  }
};

double translationError(const ObjectEstimate& e, const Eigen::Isometry3d& truth) {
  return (e.T_world_object.translation() - truth.translation()).norm();
}

// Accuracy bounds: with ~1,000+ points per object at ~0.9 m (depth sigma ~1.2 mm), the noise
// contributes well under 1 mm; what remains is convergence from 3 cm / 10 deg in 4 x 10 steps.
// 3 mm and 1.5 deg are 10x and 7x tighter than the initial error and below BOP's recall limit
// (10 % of the diameter, >= 5.8 mm for the smallest object).
constexpr double kMaxTransErr = 0.003;
constexpr double kMaxRotErrDeg = 1.5;

TEST(ObjectRefiner, OneObjectFromThreeCentimetresTenDegrees) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    Bench b;
    b.add("multimeter", 0.0, 0.0, 0.4, 10);
    const RangeMeasurements m = b.measure(seed);
    b.perturbAll(0.03, 10.0, seed);
    const RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
    ASSERT_EQ(r.objects.size(), 1u);
    const ObjectEstimate& e = r.objects[0];
    EXPECT_EQ(e.quality.status, RefineStatus::kOk) << toString(e.quality.status);
    EXPECT_LT(translationError(e, b.truth[0].second), kMaxTransErr) << "seed " << seed;
    EXPECT_LT(test::rotationErrorDeg(e.T_world_object.linear(), b.truth[0].second.linear()),
              kMaxRotErrDeg);
    EXPECT_GT(e.quality.inlier_ratio, 0.8);
    EXPECT_GT(e.quality.inliers, 500);
    EXPECT_LT(e.quality.rmse, 0.005);
    // Assigned rays are exactly the inliers; the scene holds the refined pose.
    std::size_t assigned = 0;
    for (NodeId n : r.assignment[0]) assigned += n == 10;
    EXPECT_EQ(assigned, static_cast<std::size_t>(e.quality.inliers));
    EXPECT_TRUE(b.scene.instancePose(10).isApprox(e.T_world_object));
    const RefinerOptions defaults;
    EXPECT_LT(r.rays_cast / defaults.rounds, m.size() / 8) << "casts only the rays near the object";
  }
}

// A multimeter 2.3 m away in depth noise of 4.5 mm at 1 m (24 mm there): most of its correct
// returns lie beyond the fixed 12 mm threshold, so the fit explains few of its rays; with the
// thresholds widened to 3 noise sigmas it explains most of them and stays on the object.
TEST(ObjectRefiner, ThresholdsThatFollowTheNoiseKeepAFarObjectsReturns) {
  double ratio[2] = {0, 0};
  for (int widened = 0; widened < 2; ++widened) {
    Bench b;
    b.T_world_camera = opticalLookAt({0.0, 2.0, 1.9}, {0.0, 0.0, 0.75});
    b.add("multimeter", 0.0, 0.0, 0.4, 10);
    b.scene.commit();
    const SimulatedScan scan = simulate(b.scene, *b.rays, b.T_world_camera);
    RangeMeasurements m =
        fromDepthImage(b.camera, b.rays, depthImage(scan, *b.rays), b.T_world_camera);
    addDepthNoise(m, 0.0045, 3);
    b.perturbAll(0.01, 3.0, 3);
    RefinerOptions o;
    if (widened) o.noise.depth_sigma_at_1m = 0.0045f, o.noise_sigmas = 3.0f;
    const ObjectEstimate e = ObjectRefiner(o).refine(b.scene, b.targets, {m}).objects.at(0);
    ratio[widened] = e.quality.inlier_ratio;
    if (!widened) continue;
    EXPECT_EQ(e.quality.status, RefineStatus::kOk) << toString(e.quality.status);
    EXPECT_LT(translationError(e, b.truth[0].second), 0.025);  // in noise of 24 mm
    EXPECT_GT(e.quality.rms_of_threshold, 0.0);
    EXPECT_LT(e.quality.rms_of_threshold, 0.6);  // Gaussian within 3 sigma: about 0.33 - 0.4
  }
  EXPECT_LT(ratio[0], 0.6) << "fixed thresholds";
  EXPECT_GT(ratio[1], 0.85) << "widened to the noise";
}

// The information of the fit's pairs: symmetric, positive definite for a box seen from above and
// the side, its translation part about inliers per unit normal; all zero when not asked for.
TEST(ObjectRefiner, ReportsWhatItsPairsConstrainOnlyWhenAsked) {
  Bench b;
  b.add("materialbox", 0.0, 0.0, 0.4, 10);
  const RangeMeasurements m = b.measure(1);
  b.perturbAll(0.01, 3.0, 1);
  const ObjectQuality q = ObjectRefiner().refine(b.scene, b.targets, {m}).objects.at(0).quality;
  ASSERT_EQ(q.status, RefineStatus::kOk) << toString(q.status);
  EXPECT_TRUE(q.information.isApprox(q.information.transpose()));
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Mat6>(q.information, Eigen::EigenvaluesOnly).eigenvalues()(0);
  EXPECT_GT(smallest, 0.0);
  const double translation_trace = q.information.topLeftCorner(3, 3).trace();
  EXPECT_NEAR(translation_trace, q.inliers, 1e-4 * q.inliers);
  b.perturbAll(0.01, 3.0, 1);
  RefinerOptions without;
  without.information = false;
  const ObjectQuality q0 =
      ObjectRefiner(without).refine(b.scene, b.targets, {m}).objects.at(0).quality;
  EXPECT_EQ(q0.inliers, q.inliers);
  EXPECT_TRUE(q0.information.isZero());
}

// A multimeter half a metre from the camera covers many thousand pixels. With the rays near it
// bounded to 300 per round it casts a fraction of the rays and still comes back from 1 cm / 3 deg;
// its quality counts weigh each cast ray by the rays it stands for, so they stay close to those of
// the full sampling.
TEST(ObjectRefiner, ABoundedSamplingOfANearObjectCountsWhatItStandsFor) {
  ObjectQuality q[2];
  std::size_t rays_cast[2] = {0, 0};
  for (int bounded = 0; bounded < 2; ++bounded) {
    Bench b;
    b.T_world_camera = opticalLookAt({0.0, 0.3, 1.2}, {0.0, 0.0, 0.75});
    b.add("multimeter", 0.0, 0.0, 0.4, 10);
    const RangeMeasurements m = b.measure(2);
    b.perturbAll(0.01, 3.0, 2);
    RefinerOptions o;
    o.full_resolution_last_round = false;
    if (bounded) o.max_rays_per_object = 300, o.jitter = true;
    const RefineResult r = ObjectRefiner(o).refine(b.scene, b.targets, {m});
    const ObjectEstimate& e = r.objects.at(0);
    q[bounded] = e.quality;
    rays_cast[bounded] = r.rays_cast;
    EXPECT_EQ(e.quality.status, RefineStatus::kOk) << toString(e.quality.status);
    EXPECT_LT(translationError(e, b.truth[0].second), kMaxTransErr) << "bounded " << bounded;
    EXPECT_LT(test::rotationErrorDeg(e.T_world_object.linear(), b.truth[0].second.linear()),
              kMaxRotErrDeg);
  }
  EXPECT_LT(rays_cast[1] * 8, rays_cast[0]) << rays_cast[1] << " of " << rays_cast[0];
  EXPECT_GT(q[0].expected, 8 * 300) << "the object is near: its rays exceed the bound";
  EXPECT_NEAR(q[1].expected, q[0].expected, 0.15 * q[0].expected);
  EXPECT_NEAR(q[1].inliers, q[0].inliers, 0.15 * q[0].inliers);
  const double trace[2] = {q[0].information.topLeftCorner(3, 3).trace(),
                           q[1].information.topLeftCorner(3, 3).trace()};
  EXPECT_NEAR(trace[1], trace[0], 0.15 * trace[0]);
}

// Two objects: a multimeter already where the depth puts it and a relay 2 cm / 5 deg off. With
// converged_step the multimeter's steps fall below it after a round or two and its rays are no
// longer cast, while the relay goes on; both end where all rounds put them, and the multimeter's
// quality (counted at the last round's tolerance) is what all rounds give it.
TEST(ObjectRefiner, AnObjectThatConvergedStopsBeingCast) {
  RefineResult r[2];
  Bench b;
  b.add("multimeter", -0.15, 0.0, 0.4, 10);
  b.add("relay", 0.15, 0.05, -0.3, 11);
  const RangeMeasurements m = b.measure(4);
  std::mt19937 rng(4);
  const Eigen::Isometry3d start[2] = {perturb(b.truth[0].second, 0.0005, 0.05, rng),
                                      perturb(b.truth[1].second, 0.02, 5.0, rng)};
  for (int early = 0; early < 2; ++early) {
    for (int k = 0; k < 2; ++k) b.scene.setInstancePose(b.truth[k].first, start[k]);
    b.scene.commit();
    RefinerOptions o;
    o.full_resolution_last_round = false;  // every round casts alike
    if (early) o.converged_step = 0.001;
    r[early] = ObjectRefiner(o).refine(b.scene, b.targets, {m});
  }
  EXPECT_LT(r[1].rays_cast, 0.8 * r[0].rays_cast) << r[1].rays_cast << " of " << r[0].rays_cast;
  for (int k = 0; k < 2; ++k) {
    const ObjectEstimate& full = r[0].objects.at(k);
    const ObjectEstimate& early = r[1].objects.at(k);
    EXPECT_EQ(early.quality.status, RefineStatus::kOk) << k;
    EXPECT_LT(translationError(early, b.truth[k].second), kMaxTransErr) << k;
    EXPECT_LT((early.T_world_object.translation() - full.T_world_object.translation()).norm(),
              0.001)
        << k;
    EXPECT_NEAR(early.quality.inliers, full.quality.inliers, 0.03 * full.quality.inliers) << k;
    EXPECT_NEAR(early.quality.expected, full.quality.expected, 0.03 * full.quality.expected) << k;
  }
}

// Rays that can pair with an object pass through its box or measure a point within its pull
// radius: a target whose pull radius is 5 mm (a well-tracked object) is cast over its box grown by
// 5 mm, not by the 4 cm roi_margin, and ends where the wide region puts it. (Both casts leave out
// the rays PairableRays rules out, so the narrow one saves a third, not more.)
TEST(ObjectRefiner, RaysThatCannotPairAreNotCast) {
  RefineResult r[2];
  Bench b;
  b.add("multimeter", 0.0, 0.0, 0.4, 10);
  const RangeMeasurements m = b.measure(5);
  std::mt19937 rng(5);
  const Eigen::Isometry3d start = perturb(b.truth[0].second, 0.002, 0.5, rng);
  for (int narrow = 0; narrow < 2; ++narrow) {
    b.scene.setInstancePose(10, start);
    b.scene.commit();
    std::vector<RefineTarget> targets = b.targets;
    if (narrow) targets[0].pull_radius = 0.005f;
    r[narrow] = ObjectRefiner().refine(b.scene, targets, {m});
  }
  EXPECT_LT(r[1].rays_cast, 0.7 * r[0].rays_cast) << r[1].rays_cast << " of " << r[0].rays_cast;
  const ObjectEstimate &wide = r[0].objects.at(0), &narrow = r[1].objects.at(0);
  EXPECT_NEAR(narrow.quality.expected, wide.quality.expected, 0.01 * wide.quality.expected);
  EXPECT_NEAR(narrow.quality.inliers, wide.quality.inliers, 0.01 * wide.quality.inliers);
  EXPECT_LT((narrow.T_world_object.translation() - wide.T_world_object.translation()).norm(), 3e-4);
  EXPECT_LT(translationError(narrow, b.truth[0].second), kMaxTransErr);
}

// Every ray of a multimeter's region (box + 4 cm) that pairs with it from 3 cm / 10 deg, by its
// cast or as a pull, is one PairableRays keeps; the rays that neither reach the box nor measure a
// point near it (the bench behind and beside it, beyond the pull margin) are left out.
TEST(PairableRays, KeepsEveryRayThatPairsAndLeavesOutMostOfTheRegion) {
  Bench b;
  b.add("multimeter", 0.0, 0.0, 0.4, 10);
  const RangeMeasurements m = b.measure(5);
  b.perturbAll(0.03, 10.0, 7);
  const RefinerOptions o;
  const std::vector<ObjectExtent> extents = {
      {b.scene.instancePose(10), b.scene.meshBox(b.scene.instanceMesh(10))}};
  const std::vector<MeshId> meshes = {b.scene.instanceMesh(10)};
  const TileSet region = TileSet::covering(*m.rays, raysNearObjects(m, extents, o.roi_margin));
  NodeGroups groups;
  groups.set(10, 0);
  const RangeTolerance tolerance(o.max_dist_first);
  const HitsLease lease = scratchHits(m.rays->width, m.rays->height);
  const auto pairs = collectRayPairs(b.scene, m, region, groups, tolerance, *lease);
  const UnexplainedPairing pulling{tolerance, o.pull_front_margin, o.roi_margin, o.pull_radius};
  const auto pulls =
      collectUnexplainedPairs(b.scene, m, region, *lease, groups, extents, meshes, pulling);
  ASSERT_GT(pairs[0].size(), 100u);
  ASSERT_GT(pulls[0].size(), 20u);
  const PairableRays pairable(m, extents, {o.roi_margin}, nullptr, tolerance);
  for (const auto* set : {&pairs[0], &pulls[0]})
    for (const RayPair& p : *set) EXPECT_TRUE(pairable(p.ray)) << "ray " << p.ray;
  TileSet kept = region;
  kept.keepRays(*m.rays, pairable);
  EXPECT_LT(kept.rayCount(), 0.7 * region.rayCount())
      << kept.rayCount() << " of " << region.rayCount();
  std::size_t counted = 0;
  kept.forEachRay(*m.rays, [&](std::size_t i) { counted += pairable(i) ? 1 : 0; });
  EXPECT_EQ(counted, kept.rayCount());
}

// A material box seen by the depth camera and by a LiDAR at the bench's height whose returns are
// 3 cm noisy. Weighed by their noise, the LiDAR's pairs count for about 1/400 of the camera's and
// the fit is the camera's; counted alike they pull it off. A fit from the camera alone is the same
// bit for bit with the weights on or off (its pairs all weigh 1).
TEST(ObjectRefiner, PairsWeighByTheirSensorsNoise) {
  Bench b;
  b.add("materialbox", 0.0, 0.0, 0.4, 10);
  const RangeMeasurements camera = b.measure(6);
  const auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  Eigen::Isometry3d T_world_lidar = pose({0.0, 0.6, 0.8}, -M_PI / 2);
  const SimulatedScan scan = simulate(b.scene, *lidar_rays, T_world_lidar);
  RangeMeasurements lidar =
      fromRanges(SpinningLidarModel::vlp16(), lidar_rays, scan.range, T_world_lidar);
  addRangeNoise(lidar, 0.03, 7);
  std::mt19937 rng(6);
  const Eigen::Isometry3d start = perturb(b.truth[0].second, 0.01, 3.0, rng);
  const auto fit = [&](bool weigh, const std::vector<RangeMeasurements>& sets) {
    b.scene.setInstancePose(10, start);
    b.scene.commit();
    RefinerOptions o;
    o.weigh_by_noise = weigh;
    o.noise.range_sigma = 0.03f;
    return ObjectRefiner(o).refine(b.scene, b.targets, sets).objects.at(0);
  };
  const ObjectEstimate alike = fit(false, {camera, lidar}), weighed = fit(true, {camera, lidar});
  const ObjectEstimate alone = fit(false, {camera});
  EXPECT_GT(fit(false, {lidar}).quality.expected, 300) << "the LiDAR sees it";
  const double error_alike = translationError(alike, b.truth[0].second);
  const double error_weighed = translationError(weighed, b.truth[0].second);
  EXPECT_LT(error_weighed, 0.7 * error_alike) << error_weighed << " against " << error_alike;
  EXPECT_LT((weighed.T_world_object.translation() - alone.T_world_object.translation()).norm(),
            0.2 * error_alike);
  EXPECT_TRUE(fit(true, {camera}).T_world_object.matrix() == alone.T_world_object.matrix());
}

// An unknown box 1.5 cm beside a well-placed object: its points are unexplained and near the
// object, so with the full pull radius they drag the object towards the box; a target whose pull
// radius is what its filter allows (a few millimetres) stays where its own surface puts it.
TEST(ObjectRefiner, APerTargetPullRadiusKeepsUnknownNeighboursFromPullingTheObject) {
  double error[2] = {0, 0};
  for (int gated = 0; gated < 2; ++gated) {
    Bench b;
    b.add("multimeter", 0.0, 0.0, 0.0, 10);
    const Eigen::AlignedBox3f box = catalog().get("multimeter").box;
    const MeshId clutter =
        b.scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.06f, 0.06f, 0.08f})));
    b.scene.addInstance(50, clutter, pose({box.max().x() + 0.015 + 0.03, 0.0, 0.79}, 0.0));
    const RangeMeasurements m = b.measure(1);
    b.scene.removeInstance(50);  // unknown to the tracker
    b.scene.commit();
    if (gated) b.targets[0].pull_radius = 0.005f;
    const RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
    error[gated] = translationError(r.objects[0], b.truth[0].second);
  }
  EXPECT_LT(error[1], 0.001) << "gated: " << error[1] << " m";
  EXPECT_GT(error[0], 2.0 * error[1]) << "full radius: " << error[0] << " m";
}

TEST(ObjectRefiner, UmeyamaPointToPlaneConvergesGivenEnoughSteps) {
  // RMCL's point-to-plane Umeyama iteration is a slow fixed-point iteration: it reaches the
  // same accuracy as the default solver, but needs 16 rounds x 30 steps instead of 8 x 3.
  Bench b;
  b.add("multimeter", 0.0, 0.0, -0.3, 10);
  const RangeMeasurements m = b.measure(4);
  b.perturbAll(0.02, 5.0, 4);
  RefinerOptions o;
  o.solver = StepSolver::kUmeyamaPointToPlane;
  o.rounds = 16;
  o.steps = 30;
  const RefineResult r = ObjectRefiner(o).refine(b.scene, b.targets, {m});
  EXPECT_LT(translationError(r.objects[0], b.truth[0].second), kMaxTransErr);
  EXPECT_LT(
      test::rotationErrorDeg(r.objects[0].T_world_object.linear(), b.truth[0].second.linear()),
      kMaxRotErrDeg);
}

TEST(ObjectRefiner, FiveObjectsOccludingEachOther) {
  // Seen from the camera (at +y, looking toward -y), the relay and screwdriver stand in front of
  // the KLT and the multimeter in front of the material box: the hidden ones are refined from
  // what is visible of them. Initial error 3 cm / 10 deg: beyond the thin screwdriver's radius,
  // so it converges only through the pull pairs of its unexplained points.
  for (std::uint32_t seed : {5u, 6u, 7u}) {
    Bench b;
    b.add("klt", 0.0, -0.2, 0.0, 10);
    b.add("relay", 0.05, 0.0, 0.3, 11);
    b.add("screwdriver", -0.12, 0.02, 0.2, 12);
    b.add("materialbox", 0.4, -0.15, 0.1, 13);
    b.add("multimeter", 0.38, 0.05, -0.1, 14);
    const RangeMeasurements m = b.measure(seed);
    b.perturbAll(0.03, 10.0, seed);
    const RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
    for (std::size_t k = 0; k < r.objects.size(); ++k) {
      const auto& e = r.objects[k];
      EXPECT_EQ(e.quality.status, RefineStatus::kOk) << e.node << " " << toString(e.quality.status);
      EXPECT_LT(translationError(e, b.truth[k].second), kMaxTransErr)
          << "node " << e.node << " seed " << seed;
      double rot = 1e9;  // symmetry-aware: the KLT's 180 deg turn and the screwdriver's axis
      for (const auto& S : b.targets[k].symmetry->sampled(M_PI / 180.0))
        rot = std::min(rot, test::rotationErrorDeg(e.T_world_object.linear(),
                                                   (b.truth[k].second * S).linear()));
      EXPECT_LT(rot, kMaxRotErrDeg) << "node " << e.node << " seed " << seed;
    }
  }
}

// The result does not depend on how the work is spread over threads: one thread and all of them
// give the same poses to the last bit (pairs are kept in tile order and the alignment's sums are
// split the same way). Before, the order in which threads appended their pairs changed the float
// sums, and whole evaluation runs differed (detector demo recall 0.976-0.997 over 21 runs).
TEST(ObjectRefiner, ResultsDoNotDependOnTheThreads) {
  const auto refineWith = [](int threads) {
    Bench b;
    b.add("klt", 0.0, -0.2, 0.0, 10);
    b.add("screwdriver", -0.12, 0.02, 0.2, 12);
    b.add("multimeter", 0.38, 0.05, -0.1, 14);
    const RangeMeasurements m = b.measure(9);
    b.perturbAll(0.03, 10.0, 9);
    RefineResult r;
    tbb::task_arena(threads).execute([&] { r = ObjectRefiner().refine(b.scene, b.targets, {m}); });
    return r;
  };
  if (tbb::this_task_arena::max_concurrency() < 2)
    GTEST_SKIP() << "one hardware thread: nothing to compare";
  const RefineResult one = refineWith(1), all = refineWith(tbb::this_task_arena::max_concurrency());
  ASSERT_EQ(one.objects.size(), all.objects.size());
  for (std::size_t k = 0; k < one.objects.size(); ++k) {
    EXPECT_TRUE(one.objects[k].T_world_object.matrix() == all.objects[k].T_world_object.matrix())
        << "object " << k;
    EXPECT_EQ(one.objects[k].quality.inliers, all.objects[k].quality.inliers);
  }
  EXPECT_EQ(one.assignment, all.assignment);
}

TEST(ObjectRefiner, FalseHypothesisIsFlagged) {
  // A hypothesis of a material box hovering where there is nothing: its rays measure the wall.
  Bench b;
  b.add("multimeter", 0.0, 0.0, 0.0, 10);
  const RangeMeasurements m = b.measure(6);
  const MeshId box = b.scene.addMesh(catalog().get("materialbox").mesh);
  b.scene.addInstance(20, box, pose({-0.4, -0.1, 0.95}, 0.2));
  b.targets.push_back({20, nullptr});
  b.scene.commit();
  const RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
  EXPECT_EQ(r.objects[0].quality.status, RefineStatus::kOk);
  EXPECT_EQ(r.objects[1].quality.status, RefineStatus::kFalseHypothesis);
  EXPECT_LT(r.objects[1].quality.inlier_ratio, 0.05);
  EXPECT_GT(r.objects[1].quality.expected, 500);
}

TEST(ObjectRefiner, SymmetricObjectIsNotSpunAboutItsAxis) {
  // The screwdriver is symmetric about its x axis: any roll fits the data equally well, so the
  // refiner must leave the roll where it started and fix the rest.
  Bench b;
  b.add("screwdriver", 0.0, 0.0, 0.5, 10);
  const RangeMeasurements m = b.measure(7);
  const Eigen::Isometry3d truth = b.truth[0].second;
  Eigen::Isometry3d init = truth;
  // Small offset: thin objects do not yet converge reliably from centimetres (issue 3 open).
  init.translation() += Eigen::Vector3d(0.004, -0.004, 0.004);
  init.linear() = truth.linear() *
                  Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                  Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b.scene.setInstancePose(10, init);
  b.scene.commit();
  const RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
  const Eigen::Isometry3d& est = r.objects[0].T_world_object;
  EXPECT_LT((est.translation() - truth.translation()).norm(), kMaxTransErr);
  // The axis is found ...
  const Eigen::Vector3d axis_est = est.linear().col(0), axis_true = truth.linear().col(0);
  EXPECT_LT(std::acos(std::min(1.0, axis_est.dot(axis_true))) * 180.0 / M_PI, kMaxRotErrDeg);
  // ... and the roll about it is unchanged from the initial 0.6 rad.
  const Eigen::Matrix3d rel = truth.linear().transpose() * est.linear();
  EXPECT_NEAR(std::atan2(rel(2, 1), rel(1, 1)), 0.6, 0.03);
}

TEST(ObjectRefiner, NoPointsAndAllNanDepthKeepThePose) {
  Bench b;
  b.add("relay", 0.0, 0.0, 0.0, 10);
  b.scene.commit();
  const Eigen::Isometry3d before = b.scene.instancePose(10);
  // All-NaN depth image.
  const std::vector<float> nan_depth(b.rays->size(), std::numeric_limits<float>::quiet_NaN());
  const RangeMeasurements m = fromDepthImage(b.camera, b.rays, nan_depth, b.T_world_camera);
  RefineResult r = ObjectRefiner().refine(b.scene, b.targets, {m});
  EXPECT_EQ(r.objects[0].quality.status, RefineStatus::kNotVisible);
  EXPECT_TRUE(r.objects[0].T_world_object.isApprox(before));
  // No measurement sets at all.
  r = ObjectRefiner().refine(b.scene, b.targets, {});
  EXPECT_EQ(r.objects[0].quality.status, RefineStatus::kNotVisible);
  EXPECT_TRUE(b.scene.instancePose(10).isApprox(before));
  // A depth image of the wrong size is an error, not a silent loss.
  EXPECT_THROW(fromDepthImage(b.camera, b.rays, std::vector<float>(100, 1.0f), b.T_world_camera),
               std::invalid_argument);
}

// Points on three faces of a box, every other one measured 1 cm out along its face's normal:
// unweighted, the point-to-plane fit meets the two halves in the middle; with the shifted half
// weighing three times the other, three quarters of the way out.
TEST(AlignPairs, WeightsMoveTheFitTowardsTheHeavierPairs) {
  std::vector<Eigen::Vector3f> moving, fixed, normals;
  std::vector<float> weights;
  for (int face = 0; face < 3; ++face)
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) {
        Eigen::Vector3f p = Eigen::Vector3f::Zero();
        p((face + 1) % 3) = 0.01f * i;
        p((face + 2) % 3) = 0.01f * j;
        const Eigen::Vector3f n = Eigen::Vector3f::Unit(face);
        const bool shifted = (i + j) % 2 == 0;
        moving.push_back(p);
        fixed.push_back(shifted ? Eigen::Vector3f(p + 0.01f * n) : p);
        normals.push_back(n);
        weights.push_back(shifted ? 3.0f : 1.0f);
      }
  const AlignmentOptions options;
  const auto fit = [&](const std::vector<float>* w) {
    return alignPairs(moving, fixed, normals, NormalSide::kMoving, StepSolver::kLinearPointToPlane,
                      5, 1e-9, options, w)
        .T.translation();
  };
  const Eigen::Vector3d alike = fit(nullptr), weighted = fit(&weights);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(alike(a), 0.005, 0.0005) << a;
    EXPECT_NEAR(weighted(a), 0.0075, 0.0005) << a;
  }
  const std::vector<float> ones(weights.size(), 1.0f);
  EXPECT_TRUE(fit(&ones).isApprox(alike)) << "weights of one change nothing";
}

TEST(AlignPairs, APriorHoldsWhatThePairsLeaveFreeAndIsWeighedAgainstTheRest) {
  // A plane at z = 0 measured 1 cm higher: its pairs fix the height, tilt nothing and leave the
  // in-plane shift and the turn about z free.
  std::vector<Eigen::Vector3f> moving, fixed, normals;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      const Eigen::Vector3f p(0.01f * i - 0.045f, 0.01f * j - 0.045f, 0.0f);
      moving.push_back(p), fixed.push_back(p + Eigen::Vector3f(0, 0, 0.01f));
      normals.push_back(Eigen::Vector3f::UnitZ());
    }
  AlignmentOptions options;
  options.reject_planar = false;
  AlignmentPrior prior;  // [rotation, translation]
  prior.T =
      Eigen::Translation3d(0.004, -0.003, 0.0) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ());
  prior.information.diagonal() << 1e6, 1e6, 1e6, 1e6, 1e6, 100.0;  // z: as much as the 100 pairs
  const auto fit = [&](const AlignmentPrior* p) {
    return alignPairs(moving, fixed, normals, NormalSide::kMoving, StepSolver::kLinearPointToPlane,
                      10, 1e-12, options, nullptr, p)
        .T;
  };
  const Eigen::Isometry3d free = fit(nullptr), held = fit(&prior);
  EXPECT_NEAR(free.translation().z(), 0.01, 1e-6);
  EXPECT_NEAR(free.translation().head<2>().norm(), 0.0, 1e-6) << "nothing moves what is free";
  EXPECT_NEAR(held.translation().x(), 0.004, 1e-5) << "the prior places what the pairs leave free";
  EXPECT_NEAR(held.translation().y(), -0.003, 1e-5);
  EXPECT_NEAR(Eigen::AngleAxisd(held.linear()).angle(), 0.1, 1e-4);
  EXPECT_NEAR(held.translation().z(), 0.005, 1e-5) << "equal information: half way";
}

TEST(Umeyama, RecoversAKnownTransformAndFixesReflections) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  Eigen::Isometry3d T = pose({0.3, -0.2, 0.1}, 0.7);
  T.rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  PairMoments m;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng));
    m.add(a, T * a);
  }
  const Alignment a = umeyama(m);
  ASSERT_TRUE(a.ok());
  EXPECT_TRUE(a.T.isApprox(T, 1e-9));
  EXPECT_NEAR(a.T.linear().determinant(), 1.0, 1e-12);
  // Mirrored data: the best proper rotation, never a reflection.
  PairMoments mirrored;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng));
    mirrored.add(a, Eigen::Vector3d(-a.x(), a.y(), a.z()));
  }
  EXPECT_NEAR(umeyama(mirrored).T.linear().determinant(), 1.0, 1e-12);
  // Degenerate sets.
  PairMoments line, plane, few;
  for (int i = 0; i < 50; ++i) {
    line.add(Eigen::Vector3d(0.01 * i, 0, 0), Eigen::Vector3d(0.01 * i, 0, 0));
    plane.add(Eigen::Vector3d(u(rng), u(rng), 0), Eigen::Vector3d(0, 0, 0));
  }
  few.add(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(umeyama(line).status, AlignmentStatus::kCollinear);
  EXPECT_EQ(umeyama(plane).status, AlignmentStatus::kPlanar);
  EXPECT_EQ(umeyama(few).status, AlignmentStatus::kTooFewPoints);
}

}  // namespace
}  // namespace sgt
