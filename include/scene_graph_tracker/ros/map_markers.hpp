// rviz markers of the static world, published once (latched) by the tracker: the map mesh as a
// triangle list and each piece of furniture as a translucent box with its name. They travel over
// ROS, so rviz shows the user's map on any machine, without the mesh file there.
#pragma once

#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"
#include "scene_graph_tracker/relations/scene_relations.hpp"

namespace sgt::ros {

// Namespaces "static_map" (one TRIANGLE_LIST; a mesh of more than `max_triangles` triangles is
// thinned evenly to at most that many: the latched message stays in the publisher's memory, 72
// bytes a triangle, and rviz stays fluid), "furniture" (CUBE) and "furniture_names"
// (TEXT_VIEW_FACING), in `frame`.
visualization_msgs::MarkerArray mapMarkers(const TriangleMesh& map,
                                           const std::vector<relations::Entity>& furniture,
                                           const std::string& frame,
                                           std::size_t max_triangles = 100000);

}  // namespace sgt::ros
