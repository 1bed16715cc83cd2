// Training labels of the keypoint detector: the symmetry-canonical label pose (the same label for
// every symmetric twin of a pose, the pose itself for an asymmetric object), the cuboid labels
// (one label for every half turn of the box) and the projected
// cuboid keypoints with their inside-the-image flags.
#include <gtest/gtest.h>

#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/detection/label_kind.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "support.hpp"

namespace sgt::detection {
namespace {

Eigen::Isometry3d pose(double rx, double ry, double rz, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

TEST(KeypointLabels, AsymmetricObjectKeepsItsPose) {
  const Eigen::Isometry3d T = pose(0.3, -0.2, 1.1, {0.1, 0.0, 1.0});
  EXPECT_TRUE(canonicalSymmetricPose(T, Symmetry{}).isApprox(T));
}

TEST(KeypointLabels, DiscreteTwinsGetOneLabel) {
  Symmetry klt;  // 180 degrees about z
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  klt.discrete.push_back(S);
  for (double yaw : {0.2, 1.4, 2.9, -2.0}) {
    const Eigen::Isometry3d T = pose(-2.2, 0.1, yaw, {0.0, 0.1, 1.2});
    const Eigen::Isometry3d a = canonicalSymmetricPose(T, klt),
                            b = canonicalSymmetricPose(T * S, klt);
    EXPECT_TRUE(a.isApprox(b, 1e-9)) << "yaw " << yaw;
    EXPECT_TRUE(a.isApprox(T) || a.isApprox(T * S)) << "the label is one of the twins";
    // ... the one closer to the canonical camera-frame rotation.
    const auto angle = [](const Eigen::Matrix3d& R) {
      return Eigen::AngleAxisd(canonicalLabelRotation().transpose() * R).angle();
    };
    EXPECT_LE(angle(a.linear()), std::min(angle(T.linear()), angle((T * S).linear())) + 1e-9);
  }
}

TEST(KeypointLabels, ContinuousSymmetryLabelIsStableUnderTheAxisRotation) {
  Symmetry screwdriver;
  screwdriver.continuous.push_back({Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero()});
  const Eigen::Isometry3d T = pose(0.0, 0.4, 0.7, {0.0, 0.0, 0.8});
  const Eigen::Isometry3d base = canonicalSymmetricPose(T, screwdriver);
  for (double spin : {0.5, 1.7, -2.6}) {
    Eigen::Isometry3d R = Eigen::Isometry3d::Identity();
    R.linear() = Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Isometry3d other = canonicalSymmetricPose(T * R, screwdriver);
    // Sampled every 5 degrees: the labels agree to within one step.
    EXPECT_LT(test::rotationErrorDeg(other.linear(), base.linear()), 5.01) << "spin " << spin;
    EXPECT_TRUE(other.translation().isApprox(T.translation()));
  }
}

TEST(KeypointLabels, CuboidLabelsAreOneForEveryHalfTurnOfTheBox) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.1, -0.05, -0.03),
                                Eigen::Vector3d(0.1, 0.05, 0.03));
  const PinholeModel cam;
  for (double yaw : {0.2, 1.4, 2.9, -2.0}) {
    const Eigen::Isometry3d T = pose(-2.2, 0.1, yaw, {0.0, 0.1, 1.2});
    const Eigen::Isometry3d label = canonicalCuboidPose(T, Symmetry{});
    bool is_a_turn = false;
    for (const Eigen::Isometry3d& B : boxHalfTurns()) {
      EXPECT_TRUE(canonicalCuboidPose(T * B, Symmetry{}).isApprox(label, 1e-9)) << "yaw " << yaw;
      is_a_turn = is_a_turn || label.isApprox(T * B, 1e-9);
    }
    EXPECT_TRUE(is_a_turn) << "the label is the pose turned by one of the box's half turns";
    // The same cuboid: the labelled corners are the true corners, in another order.
    const auto a = projectCuboid(cam, T, box), b = projectCuboid(cam, label, box);
    for (int k = 0; k < kCuboidKeypoints; ++k) {
      double nearest = 1e9;
      for (int m = 0; m < kCuboidKeypoints; ++m)
        nearest = std::min(nearest, (b.uv[k] - a.uv[m]).norm());
      EXPECT_LT(nearest, 1e-6) << "keypoint " << k;
    }
  }
  // Without symmetries the object labels keep the pose; the cuboid labels turn it when a turn
  // is closer to the canonical rotation (here the box seen upside down).
  const Eigen::Isometry3d upside_down =
      pose(0.0, 0.0, 0.0, {0.0, 0.0, 1.0});  // object z away from the camera
  EXPECT_TRUE(canonicalSymmetricPose(upside_down, Symmetry{}).isApprox(upside_down));
  EXPECT_FALSE(canonicalCuboidPose(upside_down, Symmetry{}).isApprox(upside_down));
}

ObjectClass boxClass(const Eigen::Vector3f& size) {
  ObjectClass c;
  c.name = "box";
  c.mesh = std::make_shared<TriangleMesh>(makeBox(size));
  c.box = c.mesh->boundingBox();
  c.diameter = c.mesh->diameter();
  return c;
}

// Shape labels: a plain cube's 24 turns look alike, so a quarter turn of it keeps its label; a
// plain box of three different sides has its three half turns; object labels keep the pose.
TEST(KeypointLabels, ShapeLabelsAreOneForEveryTurnThatLooksAlike) {
  const ObjectClass cube = boxClass(Eigen::Vector3f::Constant(0.085f));
  const Symmetry shape = labelSymmetry(cube, LabelKind::kShape);
  EXPECT_EQ(shape.discrete.size(), 23u);
  EXPECT_TRUE(labelSymmetry(cube, LabelKind::kObject).discrete.empty());
  EXPECT_EQ(labelSymmetry(boxClass({0.1f, 0.2f, 0.3f}), LabelKind::kShape).discrete.size(), 3u);
  const Eigen::Isometry3d T = pose(0.3, -0.2, 1.1, {0.1, 0.0, 0.5});
  for (const Eigen::Isometry3d& turn : {pose(0, 0, M_PI / 2, Eigen::Vector3d::Zero()),
                                        pose(M_PI / 2, 0, 0, Eigen::Vector3d::Zero()),
                                        pose(0, M_PI / 2, M_PI, Eigen::Vector3d::Zero())}) {
    EXPECT_TRUE(labelPose(T * turn, shape, LabelKind::kShape)
                    .isApprox(labelPose(T, shape, LabelKind::kShape), 1e-9));
    EXPECT_FALSE(labelPose(T * turn, Symmetry{}, LabelKind::kObject)
                     .isApprox(labelPose(T, Symmetry{}, LabelKind::kObject), 1e-3));
  }
  EXPECT_EQ(parseLabelKind("shape"), LabelKind::kShape);
  EXPECT_FALSE(parseLabelKind("cube").has_value());
  EXPECT_STREQ(labelKindName(LabelKind::kCuboid), "cuboid");
}

TEST(KeypointLabels, ProjectionMarksWhatLandsInTheImage) {
  const PinholeModel cam;
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.1, -0.05, -0.02),
                                Eigen::Vector3d(0.1, 0.05, 0.02));
  // Centred in front of the camera: all nine inside, the centre on the principal point.
  auto p = projectCuboid(cam, pose(0, 0, 0, {0, 0, 1.0}), box);
  for (int k = 0; k < kCuboidKeypoints; ++k) EXPECT_TRUE(p.inside[k]) << k;
  EXPECT_TRUE(p.uv[8].isApprox(Eigen::Vector2d(cam.cx, cam.cy)));
  // Front top right (+x +y +z) at z = 1.02 m (the object frame is the camera frame turned by
  // nothing).
  EXPECT_NEAR(p.uv[0].x(), cam.cx + cam.fx * 0.1 / 1.02, 1e-9);
  EXPECT_NEAR(p.uv[0].y(), cam.cy + cam.fy * 0.05 / 1.02, 1e-9);
  // Half out of the image on the right: the +x corners are outside (and zero), the -x inside.
  const double x_edge = (cam.width - 0.5 - cam.cx) / cam.fx;  // at z = 1
  p = projectCuboid(cam, pose(0, 0, 0, {x_edge, 0, 1.0}), box);
  EXPECT_FALSE(p.inside[0]);
  EXPECT_TRUE(p.uv[0].isZero());
  EXPECT_TRUE(p.inside[1]);
  // Behind the camera: nothing inside.
  p = projectCuboid(cam, pose(0, 0, 0, {0, 0, -1.0}), box);
  for (int k = 0; k < kCuboidKeypoints; ++k) EXPECT_FALSE(p.inside[k]) << k;
}

}  // namespace
}  // namespace sgt::detection
