// Polygon triangulation for mesh faces of more than three corners: ear clipping keeps the
// triangles of a concave outline inside it and covers its area exactly once.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "scene_graph_tracker/geometry/polygon_triangulation.hpp"

namespace sgt {
namespace {

using Corners = std::vector<Eigen::Vector3f>;

// Corners in the plane z = 0 mapped by a rotation and an offset, so the test does not rely on
// the polygon being axis-aligned.
Corners placed(const std::vector<Eigen::Vector2f>& xy) {
  const Eigen::Matrix3f R =
      Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1.0f, 2.0f, 0.5f).normalized()).toRotationMatrix();
  Corners out;
  for (const auto& p : xy)
    out.push_back(R * Eigen::Vector3f(p.x(), p.y(), 0.0f) + Eigen::Vector3f(3, -1, 2));
  return out;
}

Eigen::Vector3f triangleNormal(const Corners& c, const std::array<int, 3>& t) {
  return (c[t[1]] - c[t[0]]).cross(c[t[2]] - c[t[0]]);
}

// Sum of the triangles' areas, and whether each is wound like `normal`.
double checkedArea(const Corners& c, const std::vector<std::array<int, 3>>& tris,
                   const Eigen::Vector3f& normal) {
  double area = 0.0;
  for (const auto& t : tris) {
    const Eigen::Vector3f n = triangleNormal(c, t);
    EXPECT_GT(n.dot(normal), 0.0f) << t[0] << " " << t[1] << " " << t[2];
    area += 0.5 * n.norm();
  }
  return area;
}

Eigen::Vector3f planeNormal(const Corners& c) { return (c[1] - c[0]).cross(c[2] - c[0]); }

TEST(PolygonTriangulation, ConvexQuad) {
  const Corners c = placed({{0, 0}, {2, 0}, {2, 1}, {0, 1}});
  const auto tris = triangulatePolygon(c);
  ASSERT_EQ(tris.size(), 2u);
  EXPECT_NEAR(checkedArea(c, tris, planeNormal(c)), 2.0, 1e-5);
}

// An L-shaped panel: its reflex corner (index 3) makes a fan from corner 0 leave the outline.
TEST(PolygonTriangulation, ConcaveOutlineIsCoveredExactlyOnce) {
  const Corners c = placed({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  const auto tris = triangulatePolygon(c);
  ASSERT_EQ(tris.size(), 4u);
  EXPECT_NEAR(checkedArea(c, tris, planeNormal(c)), 3.0, 1e-5);
}

// A comb of 40 teeth, clockwise: many reflex corners, winding kept as authored.
TEST(PolygonTriangulation, ClockwiseComb) {
  std::vector<Eigen::Vector2f> xy;
  for (int k = 0; k < 40; ++k) {
    xy.emplace_back(2 * k, 0);
    xy.emplace_back(2 * k + 1, 3);
  }
  xy.emplace_back(79, -1);
  xy.emplace_back(0, -1);
  const Corners c = placed(xy);
  const auto tris = triangulatePolygon(c);
  ASSERT_EQ(tris.size(), c.size() - 2);
  double shoelace = 0.0;
  for (std::size_t i = 0; i < xy.size(); ++i)
    shoelace += xy[i].x() * xy[(i + 1) % xy.size()].y() - xy[(i + 1) % xy.size()].x() * xy[i].y();
  const Eigen::Vector3f cw = planeNormal(placed({{0, 0}, {0, 1}, {1, 0}}));  // a clockwise triangle
  EXPECT_NEAR(checkedArea(c, tris, cw), std::abs(shoelace) / 2.0, 1e-3);
}

TEST(PolygonTriangulation, DegenerateAndSelfIntersectingStillGiveNMinusTwo) {
  EXPECT_EQ(triangulatePolygon(placed({{0, 0}, {1, 0}, {2, 0}, {3, 0}})).size(), 2u);
  EXPECT_EQ(triangulatePolygon(placed({{0, 0}, {1, 1}, {1, 0}, {0, 1}})).size(), 2u);  // bow tie
  const Corners nan = {{0, 0, 0}, {1, 0, 0}, {NAN, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(triangulatePolygon(nan).size(), 2u);
}

TEST(PolygonTriangulation, RefusesTooFewOrTooManyCorners) {
  EXPECT_THROW(triangulatePolygon(placed({{0, 0}, {1, 0}})), std::invalid_argument);
  EXPECT_THROW(triangulatePolygon(Corners(kMaxPolygonCorners + 1, Eigen::Vector3f::Zero())),
               std::invalid_argument);
}

}  // namespace
}  // namespace sgt
