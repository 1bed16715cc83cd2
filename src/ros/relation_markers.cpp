#include "scene_graph_tracker/ros/relation_markers.hpp"

namespace sgt::ros {

namespace {

std_msgs::ColorRGBA relationColour(relations::Relation r) {
  std_msgs::ColorRGBA c;
  c.a = 0.9f;
  switch (r) {
    case relations::Relation::On:
      c.r = 0.2f, c.g = 0.6f, c.b = 1.0f;
      break;
    case relations::Relation::In:
      c.r = 1.0f, c.g = 0.4f, c.b = 0.1f;
      break;
    default:
      c.r = 0.85f, c.g = 0.85f, c.b = 0.85f;
      break;  // directional relations
  }
  return c;
}

geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point q;
  q.x = p.x(), q.y = p.y(), q.z = p.z();
  return q;
}

}  // namespace

std::vector<visualization_msgs::Marker> relationMarkers(
    const std::vector<relations::Edge>& edges,
    const std::map<std::string, Eigen::Vector3d>& centres, const std::string& frame,
    const ::ros::Time& stamp, int first_id) {
  std::vector<visualization_msgs::Marker> out;
  visualization_msgs::Marker lines;
  lines.header.frame_id = frame, lines.header.stamp = stamp;
  lines.ns = "relations", lines.id = first_id++, lines.type = visualization_msgs::Marker::LINE_LIST;
  lines.action = visualization_msgs::Marker::ADD;
  lines.pose.orientation.w = 1.0;
  lines.scale.x = 0.006;
  for (const relations::Edge& e : edges) {
    const auto s = centres.find(e.subject), o = centres.find(e.object);
    if (s == centres.end() || o == centres.end()) continue;
    const std_msgs::ColorRGBA c = relationColour(e.relation);
    lines.points.push_back(point(s->second)), lines.points.push_back(point(o->second));
    lines.colors.push_back(c), lines.colors.push_back(c);
    visualization_msgs::Marker label;
    label.header = lines.header;
    label.ns = "relation_labels", label.id = first_id++,
    label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    label.action = visualization_msgs::Marker::ADD;
    label.pose.position = point(0.5 * (s->second + o->second) + Eigen::Vector3d(0, 0, 0.03));
    label.pose.orientation.w = 1.0;
    label.scale.z = 0.035;
    label.color = c;
    label.text = relations::relationName(e.relation);
    out.push_back(label);
  }
  if (!lines.points.empty()) out.insert(out.begin(), lines);
  return out;
}

}  // namespace sgt::ros
