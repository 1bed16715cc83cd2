// Procedural stand-ins for the paper's five object classes, used when the real CAD meshes are
// not available (tests, benchmarks). Units are metres, the origin is the bounding-box centre and
// the extents match the real objects; the shapes carry the features that make each class
// recognisable (and its pose observable) to a depth sensor.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

// {"multimeter", "screwdriver", "materialbox", "klt", "relay"}.
const std::vector<std::string>& paperObjectClasses();

// Triangle count of the paper's CAD model of `class_name`; throws std::invalid_argument for an
// unknown class.
std::size_t paperTriangleCount(const std::string& class_name);

// Extents (x, y, z) in metres of the real object; throws std::invalid_argument when unknown.
Eigen::Vector3f paperObjectExtents(const std::string& class_name);

// Model of `class_name`, refined to at least `min_triangles` triangles when > 0 (pass
// paperTriangleCount(name) for a benchmark stand-in of the paper's mesh complexity).
// Throws std::invalid_argument naming the class for an unknown name.
TriangleMesh makeObjectModel(const std::string& class_name, std::size_t min_triangles = 0);

}  // namespace sgt
