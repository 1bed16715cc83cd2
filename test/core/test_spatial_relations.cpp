// Spatial relations with SEMAP's semantics on hand-placed boxes: every relation strict and relaxed,
// in a rotated reference frame; relaxed-but-not-strict and neither cases; the extrusion solids;
// the box tests (containment, separating axes, exact distance) against brute force.
#include <gtest/gtest.h>

#include <random>

#include "scene_graph_tracker/relations/spatial_relations.hpp"

namespace sgt::relations {
namespace {

const std::vector<Relation> kAll = {Relation::On,      Relation::In,        Relation::LeftOf,
                                    Relation::RightOf, Relation::InFrontOf, Relation::Behind,
                                    Relation::Above,   Relation::Below};

// Reference: 0.4 x 0.2 x 0.1 m, so with o = 3.5 the projections reach 1.4 / 0.7 / 0.35 m out.
OrientedBox reference(const Eigen::Isometry3d& T) { return {T, Eigen::Vector3d(0.2, 0.1, 0.05)}; }

// A small target at `p` in the reference's frame (turned a little about its own axes).
OrientedBox target(const Eigen::Isometry3d& T_world_ref, const Eigen::Vector3d& p,
                   double half = 0.02) {
  Eigen::Isometry3d T =
      T_world_ref * Eigen::Translation3d(p) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ());
  return {T, Eigen::Vector3d::Constant(half)};
}

std::vector<Eigen::Isometry3d> referencePoses() {
  Eigen::Isometry3d turned = Eigen::Isometry3d::Identity();
  turned.translate(Eigen::Vector3d(2.0, -1.0, 0.8));
  turned.rotate(Eigen::AngleAxisd(2.3, Eigen::Vector3d::UnitZ()));
  Eigen::Isometry3d tilted = turned;
  tilted.rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
  return {Eigen::Isometry3d::Identity(), turned, tilted};
}

// The centre of the projection toward the relation's side, in R's frame.
Eigen::Vector3d inProjection(Relation r) {
  const Eigen::Vector3d h(0.2, 0.1, 0.05);
  switch (r) {
    case Relation::LeftOf:
      return {0, h.y() + 3.5 * h.y(), 0};
    case Relation::RightOf:
      return {0, -h.y() - 3.5 * h.y(), 0};
    case Relation::InFrontOf:
      return {h.x() + 3.5 * h.x(), 0, 0};
    case Relation::Behind:
      return {-h.x() - 3.5 * h.x(), 0, 0};
    case Relation::Above:
      return {0, 0, h.z() + 3.5 * h.z()};
    case Relation::Below:
      return {0, 0, -h.z() - 3.5 * h.z()};
    case Relation::On:
      return {0.05, 0.03, h.z() + 0.02 + 0.005};  // 5 mm above the top face
    case Relation::In:
      return {0.1, 0.0, 0.0};
  }
  return {};
}

TEST(SpatialRelations, NamesRoundTrip) {
  for (Relation r : kAll) EXPECT_EQ(parseRelation(relationName(r)), r);
  EXPECT_STREQ(relationName(Relation::InFrontOf), "in_front_of");
  EXPECT_FALSE(parseRelation("beside").has_value());
}

TEST(SpatialRelations, EveryRelationStrictInRotatedReferences) {
  for (const Eigen::Isometry3d& T : referencePoses())
    for (Relation r : kAll) {
      const OrientedBox t = target(T, inProjection(r));
      for (Relation q : kAll) {
        // Placed for r: r holds strictly; the opposite directions do not, not even relaxed.
        const bool expect = q == r || (r == Relation::On && q == Relation::Above);
        EXPECT_EQ(holds(q, Mode::Strict, t, reference(T)), expect)
            << relationName(q) << " for " << relationName(r);
        if (expect) {
          EXPECT_TRUE(holds(q, Mode::Relaxed, t, reference(T))) << relationName(q);
        }
      }
      const Relation opposite[] = {Relation::Below,  Relation::In,     Relation::RightOf,
                                   Relation::LeftOf, Relation::Behind, Relation::InFrontOf,
                                   Relation::Below,  Relation::Above};
      if (isDirectional(r)) {
        EXPECT_FALSE(holds(opposite[static_cast<int>(r)], Mode::Relaxed, t, reference(T)))
            << relationName(r);
      }
    }
}

TEST(SpatialRelations, RelaxedButNotStrict) {
  for (const Eigen::Isometry3d& T : referencePoses()) {
    const OrientedBox R = reference(T);
    // Left of R but beyond its front face in x: outside the left projection, inside the halfspace.
    const OrientedBox diagonal = target(T, {0.35, 0.4, 0.0});
    EXPECT_FALSE(holds(Relation::LeftOf, Mode::Strict, diagonal, R));
    EXPECT_TRUE(holds(Relation::LeftOf, Mode::Relaxed, diagonal, R));
    EXPECT_TRUE(holds(Relation::InFrontOf, Mode::Relaxed, diagonal, R));
    EXPECT_FALSE(holds(Relation::InFrontOf, Mode::Strict, diagonal, R));
    // Straddling the top face's edge and resting on it: relaxed on, not strict.
    const OrientedBox overhang = target(T, {0.2, 0.0, 0.05 + 0.021}, 0.015);
    EXPECT_FALSE(holds(Relation::On, Mode::Strict, overhang, R));
    EXPECT_TRUE(holds(Relation::On, Mode::Relaxed, overhang, R));
    // Half inside R: relaxed in, not strict.
    const OrientedBox half_in = target(T, {0.2, 0.0, 0.0});
    EXPECT_FALSE(holds(Relation::In, Mode::Strict, half_in, R));
    EXPECT_TRUE(holds(Relation::In, Mode::Relaxed, half_in, R));
  }
}

TEST(SpatialRelations, Neither) {
  for (const Eigen::Isometry3d& T : referencePoses()) {
    const OrientedBox R = reference(T);
    const OrientedBox far_left = target(T, {0.0, 1.5, 0.0});  // beyond the 0.7 m extrusion
    const OrientedBox high =
        target(T, {0.0, 0.0, 0.05 + 0.02 + 0.05});  // above, 5 cm clear of the top
    for (Mode m : {Mode::Strict, Mode::Relaxed}) {
      EXPECT_FALSE(holds(Relation::LeftOf, m, far_left, R));
      EXPECT_FALSE(holds(Relation::In, m, far_left, R));
      EXPECT_FALSE(holds(Relation::On, m, high, R));
    }
    EXPECT_TRUE(holds(Relation::Above, Mode::Strict, high, R));
  }
}

TEST(SpatialRelations, ToleranceKeepsASinkingObjectOn) {
  const OrientedBox R = reference(Eigen::Isometry3d::Identity());
  const OrientedBox sunk = target(Eigen::Isometry3d::Identity(), {0, 0, 0.05 + 0.02 - 0.002}, 0.02);
  EXPECT_FALSE(holds(Relation::On, Mode::Strict, sunk, R));
  RelationOptions o;
  o.tolerance = 0.005;
  EXPECT_TRUE(holds(Relation::On, Mode::Strict, sunk, R, o));
}

TEST(SpatialRelations, ExtrusionSolids) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));  // R's front (+x) is world +y
  const OrientedBox R = reference(T);
  const OrientedBox p = projection(R, Side::Front);
  EXPECT_TRUE(p.half_extents.isApprox(Eigen::Vector3d(0.7, 0.1, 0.05)));
  EXPECT_TRUE(p.T_world_box.translation().isApprox(Eigen::Vector3d(0, 0.9, 0), 1e-12));
  const OrientedBox h = halfspace(R, Side::Bottom);
  EXPECT_TRUE(h.half_extents.isApprox(Eigen::Vector3d(0.2 + 1.4, 0.1 + 0.7, 0.175)));
  EXPECT_TRUE(h.T_world_box.translation().isApprox(Eigen::Vector3d(0, 0, -0.225), 1e-12));
  EXPECT_EQ(solidOf(Relation::LeftOf, Mode::Strict), Solid::Projection);
  EXPECT_EQ(solidOf(Relation::LeftOf, Mode::Relaxed), Solid::Halfspace);
  EXPECT_EQ(solidOf(Relation::On, Mode::Relaxed), Solid::Projection);
  EXPECT_EQ(solidOf(Relation::In, Mode::Strict), Solid::Box);
}

TEST(SpatialRelations, ViewpointLeftIsTheViewersLeft) {
  // R faces the camera (its front, +x, points at the camera at -x): in R's own frame the viewer's
  // left is R's right.
  Eigen::Isometry3d T_ref = Eigen::Isometry3d::Identity();
  T_ref.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  const OrientedBox R = reference(T_ref);
  Eigen::Isometry3d T_cam = Eigen::Isometry3d::Identity();  // optical frame looking along world +x
  T_cam.translation() = Eigen::Vector3d(-2, 0, 0.5);
  T_cam.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const OrientedBox viewer_left = {Eigen::Isometry3d(Eigen::Translation3d(0, 0.4, 0)),
                                   Eigen::Vector3d::Constant(0.02)};
  const OrientedBox nearer = {Eigen::Isometry3d(Eigen::Translation3d(-0.5, 0, 0)),
                              Eigen::Vector3d::Constant(0.02)};
  EXPECT_TRUE(holds(Relation::RightOf, Mode::Strict, viewer_left, R));
  EXPECT_TRUE(holdsFromViewpoint(Relation::LeftOf, Mode::Strict, viewer_left, R, T_cam));
  EXPECT_FALSE(holdsFromViewpoint(Relation::RightOf, Mode::Relaxed, viewer_left, R, T_cam));
  EXPECT_TRUE(holdsFromViewpoint(Relation::InFrontOf, Mode::Strict, nearer, R, T_cam));
  EXPECT_FALSE(holdsFromViewpoint(Relation::Behind, Mode::Relaxed, nearer, R, T_cam));
}

TEST(OrientedBoxes, OrientedBoxFromMeshBox) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.1, -0.05, 0.0), Eigen::Vector3d(0.1, 0.05, 0.2));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(1, 2, 3));
  T.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));  // object z -> world -y
  const OrientedBox b = orientedBox(box, T);
  EXPECT_TRUE(b.half_extents.isApprox(Eigen::Vector3d(0.1, 0.05, 0.1)));
  EXPECT_TRUE(b.T_world_box.translation().isApprox(Eigen::Vector3d(1, 1.9, 3), 1e-12));
}

// Brute force: closest pair among points sampled on both boxes' surfaces (grid spacing `step`).
std::vector<Eigen::Vector3d> surfaceSamples(const OrientedBox& b, int n) {
  std::vector<Eigen::Vector3d> out;
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0})
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d p;
          p[axis] = s;
          p[(axis + 1) % 3] = 2.0 * i / n - 1.0;
          p[(axis + 2) % 3] = 2.0 * j / n - 1.0;
          out.push_back(b.T_world_box * p.cwiseProduct(b.half_extents));
        }
  return out;
}

TEST(OrientedBoxes, DistanceAndIntersectionAgreeWithBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int separated = 0, touching = 0;
  for (int k = 0; k < 30; ++k) {
    auto random = [&] {
      OrientedBox b;
      b.T_world_box = Eigen::Translation3d(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)) *
                      Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
      b.half_extents = Eigen::Vector3d(0.1 + 0.2 * std::abs(u(rng)), 0.05 + 0.1 * std::abs(u(rng)),
                                       0.05 + 0.1 * std::abs(u(rng)));
      return b;
    };
    const OrientedBox a = random(), b = random();
    const int n = 16;
    double brute = 1e9;
    const auto sa = surfaceSamples(a, n), sb = surfaceSamples(b, n);
    for (const auto& p : sa)
      for (const auto& q : sb) brute = std::min(brute, (p - q).norm());
    const double d = distance(a, b);
    const bool hit = intersects(a, b);
    EXPECT_EQ(hit, d == 0.0);
    if (!hit) {
      ++separated;
      EXPECT_LE(d, brute + 1e-9);
      EXPECT_GE(d, brute - 0.04);  // sample spacing <= 2 * 0.3 / 16 per axis
    } else {
      ++touching;
      if (brute > 0.04) {  // surfaces far apart yet intersecting: one must lie inside the other
        EXPECT_TRUE(contains(a, b, 1e-9) || contains(b, a, 1e-9));
      }
    }
  }
  EXPECT_GT(separated, 5);
  EXPECT_GT(touching, 3);
}

TEST(OrientedBoxes, EdgeAxisSeparates) {
  // A vertical edge of a (turned 45 deg about z) faces a y-parallel edge of b (turned 45 deg about
  // y): no face axis separates them, the edge-edge axis x does; the gap is 1.5 - 2 * 0.5 * sqrt(2).
  const OrientedBox a{Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ())),
                      Eigen::Vector3d::Constant(0.5)};
  const OrientedBox b{
      Eigen::Translation3d(1.5, 0, 0) * Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()),
      Eigen::Vector3d::Constant(0.5)};
  EXPECT_FALSE(intersects(a, b));
  EXPECT_NEAR(distance(a, b), 1.5 - std::sqrt(2.0), 1e-9);
  OrientedBox closer = b;
  closer.T_world_box.translation().x() = 1.4;
  EXPECT_TRUE(intersects(a, closer));
  EXPECT_EQ(distance(a, closer), 0.0);
  const OrientedBox far{Eigen::Isometry3d(Eigen::Translation3d(2, 0, 0)),
                        Eigen::Vector3d::Constant(0.5)};
  EXPECT_NEAR(
      distance(OrientedBox{Eigen::Isometry3d::Identity(), Eigen::Vector3d::Constant(0.5)}, far),
      1.0, 1e-12);
  EXPECT_TRUE(contains(far, far));
}

}  // namespace
}  // namespace sgt::relations
