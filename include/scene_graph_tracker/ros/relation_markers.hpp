// rviz markers for relation edges: a line from the subject's box centre to the object's (colour
// by relation) and a label "on" / "in" / "left_of" ... at the line's middle, lifted a little.
#pragma once

#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <string>
#include <vector>

#include "scene_graph_tracker/relations/scene_relations.hpp"

namespace sgt::ros {

// `centres`: box centre in `frame` of every entity that may appear in an edge (tracks and
// furniture); edges naming an unknown entity are skipped. Markers in namespaces "relations" and
// "relation_labels", ids from `first_id` on.
std::vector<visualization_msgs::Marker> relationMarkers(
    const std::vector<relations::Edge>& edges,
    const std::map<std::string, Eigen::Vector3d>& centres, const std::string& frame,
    const ::ros::Time& stamp, int first_id);

}  // namespace sgt::ros
