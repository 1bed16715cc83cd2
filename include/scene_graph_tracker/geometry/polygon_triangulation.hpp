// Triangulation of one planar (or nearly planar) polygon, as mesh files store faces of more
// than three corners. Ear clipping in the polygon's best-fit plane, so concave faces (an L-shaped
// panel, a slot) are split into triangles that stay inside the outline, which a fan would not.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace sgt {

// Largest polygon triangulatePolygon accepts; a face with more corners is refused as implausible.
constexpr std::size_t kMaxPolygonCorners = 4096;

// Splits the polygon whose corners are `corners` (in order, either winding) into corners.size()-2
// triangles of corner indices, wound like the polygon. A self-intersecting outline, where no ear is
// left, is finished as a fan. Throws std::invalid_argument below 3 or above kMaxPolygonCorners.
std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<Eigen::Vector3f>& corners);

}  // namespace sgt
