// Pre-segmentation against ground truth from the simulation: things the catalog does not have
// (boxes, a person-sized cylinder) must come out as unknown, the tracked object and the map as
// themselves, and a panel the map has but the world no longer has as "behind".
#include <gtest/gtest.h>

#include <cstdio>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/segmentation/predicted_ranges.hpp"
#include "scene_graph_tracker/segmentation/presegmentation.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"
#include "support.hpp"

namespace sgt {
namespace {

constexpr NodeId kMap = 1, kTracked = 30;

struct Scores {
  double precision, recall;
  std::size_t truth;
};

class PresegmentationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.setStaticMap(std::make_shared<TriangleMesh>(building_->mesh), kMap);
    base_ = building_->robot_start.cast<double>();
    // Distractors around the robot: three boxes and a person-sized cylinder.
    const auto add = [&](NodeId node, const TriangleMesh& mesh, const Eigen::Vector3d& p) {
      scene_.addInstance(node, scene_.addMesh(std::make_shared<TriangleMesh>(mesh)),
                         test::poseXyzYaw(base_ + p));
      distractors_.push_back(node);
    };
    add(40, makeBox({0.5f, 0.4f, 0.6f}), {1.8, 0.9, 0.3});
    add(41, makeBox({0.3f, 0.3f, 0.3f}), {-1.6, 1.7, 0.15});
    add(42, makeBox({0.8f, 0.4f, 1.0f}), {0.3, -2.4, 0.5});
    add(43, makeCylinder(0.25f, 1.75f, 48), {2.2, -1.2, 0.875});
    // A known object the tracker has in its scene.
    scene_.addInstance(kTracked,
                       scene_.addMesh(std::make_shared<TriangleMesh>(makeBox({0.4f, 0.3f, 0.5f}))),
                       test::poseXyzYaw(base_ + Eigen::Vector3d(-1.5, -1.0, 0.25)));
    scene_.commit();
  }

  // Simulates `rays` from `T` with everything present, then hides the distractors from the
  // tracker's scene and pre-segments; scores the unknown label against the simulated owners.
  Scores run(const SensorModel& model, std::shared_ptr<SensorRays> rays,
             const Eigen::Isometry3d& T) {
    const SimulatedScan s = simulate(scene_, *rays, T);
    RangeMeasurements m =
        std::holds_alternative<PinholeModel>(model)
            ? fromDepthImage(std::get<PinholeModel>(model), rays, depthImage(s, *rays), T)
            : fromRanges(model, rays, s.range, T);
    if (std::holds_alternative<PinholeModel>(model))
      addDepthNoise(m, 0.0015, 5);
    else
      addRangeNoise(m, 0.01, 5);
    for (const NodeId d : distractors_) scene_.setInstanceEnabled(d, false);
    scene_.commit();
    result_ = presegment(scene_, m);
    for (const NodeId d : distractors_) scene_.setInstanceEnabled(d, true);
    scene_.commit();

    std::size_t tp = 0, fp = 0, fn = 0, object_ok = 0, object_truth = 0;
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (!m.valid(i)) {
        EXPECT_EQ(result_.label[i], PointLabel::kInvalid);
        continue;
      }
      const bool truth =
          std::find(distractors_.begin(), distractors_.end(), s.node[i]) != distractors_.end();
      const bool said = result_.label[i] == PointLabel::kUnknown;
      tp += truth && said, fp += !truth && said, fn += truth && !said;
      if (s.node[i] == kTracked) {
        ++object_truth;
        object_ok += result_.label[i] == PointLabel::kObject && result_.node[i] == kTracked;
      }
    }
    std::printf(
        "unknown: precision %.4f recall %.4f over %zu true unknown points; reduction %.3f\n",
        tp + fp ? static_cast<double>(tp) / (tp + fp) : 0.0,
        tp + fn ? static_cast<double>(tp) / (tp + fn) : 0.0, tp + fn, result_.counts.reduction());
    if (object_truth > 0) EXPECT_GE(static_cast<double>(object_ok) / object_truth, 0.98);
    EXPECT_EQ(result_.counts.unknown, result_.unknown_points.size());
    EXPECT_EQ(result_.counts.valid() + result_.counts.invalid, m.size());
    return {tp + fp ? static_cast<double>(tp) / (tp + fp) : 0.0,
            tp + fn ? static_cast<double>(tp) / (tp + fn) : 0.0, tp + fn};
  }

  const Building* building_ = &test::coarseBuilding();
  RaycastScene scene_;
  Eigen::Vector3d base_;
  std::vector<NodeId> distractors_;
  Presegmentation result_;
};

TEST_F(PresegmentationTest, LidarFindsTheUnknownThings) {
  auto rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const Scores s =
      run(SpinningLidarModel::vlp16(), rays, test::poseXyzYaw(base_ + Eigen::Vector3d(0, 0, 0.9)));
  ASSERT_GT(s.truth, 300u);  // the distractors are in view
  // The goals: precision >= 0.95, recall >= 0.98.
  EXPECT_GE(s.precision, 0.95);
  EXPECT_GE(s.recall, 0.98);
  EXPECT_GT(result_.counts.reduction(), 0.5);  // most of the scan is map
}

TEST_F(PresegmentationTest, DepthCameraFindsTheUnknownThings) {
  const PinholeModel cam = PinholeModel::xtion();
  auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const Eigen::Vector3d eye = base_ + Eigen::Vector3d(0, 0, 1.2);
  const Scores s = run(cam, rays, opticalLookAt(eye, base_ + Eigen::Vector3d(2.0, -0.4, 0.4)));
  ASSERT_GT(s.truth, 3000u);
  EXPECT_GE(s.precision, 0.95);
  EXPECT_GE(s.recall, 0.98);
}

TEST_F(PresegmentationTest, MeasurementsBehindARemovedPanelAreLabelledBehind) {
  // The tracker's scene has a panel (say a door leaf the map knows) that the world lost.
  const MeshId panel = scene_.addMesh(std::make_shared<TriangleMesh>(makeBox({0.05f, 1.0f, 2.0f})));
  scene_.addInstance(50, panel, test::poseXyzYaw(base_ + Eigen::Vector3d(-0.8, 0.0, 1.0)));
  scene_.setInstanceEnabled(50, false);
  scene_.commit();
  auto rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const Eigen::Isometry3d T = test::poseXyzYaw(base_ + Eigen::Vector3d(0, 0, 0.9));
  const SimulatedScan s = simulate(scene_, *rays, T);
  scene_.setInstanceEnabled(50, true);
  scene_.commit();
  RayHits predicted;
  scene_.cast(*rays, T, predicted);
  const Presegmentation p =
      presegment(scene_, fromRanges(SpinningLidarModel::vlp16(), rays, s.range, T));
  std::size_t through_panel = 0, behind = 0;
  for (std::size_t i = 0; i < s.range.size(); ++i) {
    if (predicted.node[i] != 50 || !std::isfinite(s.range[i])) continue;
    ++through_panel;
    behind += p.label[i] == PointLabel::kBehind;
  }
  ASSERT_GT(through_panel, 50u);
  EXPECT_EQ(behind, through_panel);
  EXPECT_EQ(p.counts.behind, behind);
}

// The depth image's predicted ranges taken from the map's planes where blocks of pixels see one
// agree with a cast per ray, at a fraction of the rays cast; the known box and the distractors
// (enabled: the tracker's scene has them) are cast ray by ray.
// Ranges taken from the map's planes where blocks of rays see one agree with a cast per ray, at a
// fraction of the rays cast; the known box and the distractors (enabled: the tracker's scene has
// them) are cast ray by ray. Returns the rays cast.
std::size_t expectRangesFromPlanesAgree(const RaycastScene& scene, const RangeMeasurements& m,
                                        std::size_t min_object_rays) {
  RayHits every, planes;
  EXPECT_EQ(predictRanges(scene, m, every, false), m.size());
  const std::size_t cast = predictRanges(scene, m, planes, true);
  std::size_t hit = 0, same_node = 0, within_mm = 0, objects = 0, objects_same = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!every.hit(i)) {
      EXPECT_FALSE(planes.hit(i)) << "ray " << i;
      continue;
    }
    ++hit;
    same_node += planes.node[i] == every.node[i];
    within_mm += std::abs(planes.range[i] - every.range[i]) < 1e-3f;
    if (every.node[i] == kMap) continue;
    ++objects;
    objects_same += planes.node[i] == every.node[i] && planes.range[i] == every.range[i];
  }
  std::printf(
      "rays cast %zu of %zu; of %zu rays that hit (%zu objects) %zu on the same node, %zu "
      "within 1 mm\n",
      cast, m.size(), hit, objects, same_node, within_mm);
  EXPECT_GT(objects, min_object_rays);
  EXPECT_EQ(objects_same, objects);  // the objects' rays are cast
  EXPECT_GE(static_cast<double>(same_node) / hit, 0.999);
  EXPECT_GE(static_cast<double>(within_mm) / hit, 0.999);
  return cast;
}

TEST_F(PresegmentationTest, DepthRangesFromTheMapsPlanesAgreeWithACastPerRay) {
  const PinholeModel cam = PinholeModel::xtion();
  auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const Eigen::Vector3d eye = base_ + Eigen::Vector3d(0, 0, 1.2);
  const Eigen::Isometry3d T = opticalLookAt(eye, base_ + Eigen::Vector3d(2.0, -0.4, 0.4));
  const RangeMeasurements m = fromDepthImage(cam, rays, std::vector<float>(rays->size(), 1.0f), T);
  EXPECT_LT(expectRangesFromPlanesAgree(scene_, m, 3000), m.size() / 2);  // a fifth see boxes
}

TEST_F(PresegmentationTest, LidarRangesAreCastRayByRay) {
  auto rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  const Eigen::Isometry3d T = test::poseXyzYaw(base_ + Eigen::Vector3d(0, 0, 0.9));
  const RangeMeasurements m =
      fromRanges(SpinningLidarModel::vlp16(), rays, std::vector<float>(rays->size(), 1.0f), T);
  EXPECT_EQ(expectRangesFromPlanesAgree(scene_, m, 300), m.size());  // every ray cast
}

// A desk as the whole map (as a real sequence's plane) and a box on it, seen from above its far
// edge: blocks whose corners miss everything predict no hit, and agree with a cast per ray.
TEST(Presegmentation, RangesWhereBlocksSeeNothingAgreeWithACastPerRay) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({1.2f, 0.8f, 0.02f})), kMap);
  scene.addInstance(kTracked,
                    scene.addMesh(std::make_shared<TriangleMesh>(makeBox({0.1f, 0.1f, 0.1f}))),
                    test::poseXyzYaw({0.2, 0.1, 0.06}));
  scene.commit();
  const PinholeModel cam = PinholeModel::xtion();
  auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const Eigen::Isometry3d T = opticalLookAt({-0.9, 0.0, 0.5}, {0.5, 0.0, 0.0});
  const RangeMeasurements m = fromDepthImage(cam, rays, std::vector<float>(rays->size(), 1.0f), T);
  const std::size_t cast = expectRangesFromPlanesAgree(scene, m, 300);
  RayHits every;
  scene.cast(*rays, T, every, nullptr, {}, kRangeAndNodeOnly);
  std::size_t missing = 0;
  for (std::size_t i = 0; i < rays->size(); ++i) missing += !every.hit(i);
  ASSERT_GT(missing, rays->size() / 4);  // the desk's far edge is in view
  EXPECT_LT(cast, rays->size() / 3);
}

TEST(Presegmentation, InvalidAndEmptyInput) {
  RaycastScene scene;
  scene.setStaticMap(std::make_shared<TriangleMesh>(makeBox({10, 10, 0.1f})), kMap);
  scene.commit();
  auto rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
  RangeMeasurements m =
      fromRanges(SpinningLidarModel::vlp16(), rays,
                 std::vector<float>(rays->size(), std::numeric_limits<float>::quiet_NaN()),
                 test::poseXyzYaw({0, 0, 1}));
  const Presegmentation p = presegment(scene, m);
  EXPECT_EQ(p.counts.invalid, rays->size());
  EXPECT_EQ(p.counts.valid(), 0u);
  EXPECT_TRUE(p.unknown_points.empty());
  EXPECT_EQ(p.counts.reduction(), 0.0);
  auto empty_rays = std::make_shared<SensorRays>();
  const Presegmentation e = presegment(
      scene, fromRanges(SpinningLidarModel::vlp16(), empty_rays, {}, test::poseXyzYaw({0, 0, 1})));
  EXPECT_TRUE(e.label.empty());
}

}  // namespace
}  // namespace sgt
