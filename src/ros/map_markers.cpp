#include "scene_graph_tracker/ros/map_markers.hpp"

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

visualization_msgs::Marker marker(const std::string& frame, const char* ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame, m.ns = ns, m.id = id, m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.frame_locked = true;
  return m;
}

visualization_msgs::Marker meshMarker(const TriangleMesh& map, const std::string& frame,
                                      std::size_t max_triangles) {
  visualization_msgs::Marker m =
      marker(frame, "static_map", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  m.color.r = m.color.g = m.color.b = 0.75f, m.color.a = 1.0f;
  const std::size_t n = map.triangles.size();
  const std::size_t step =
      max_triangles > 0 && n > max_triangles ? (n + max_triangles - 1) / max_triangles : 1;
  m.points.reserve(3 * (n / step + 1));
  for (std::size_t k = 0; k < n; k += step)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3f& v = map.vertices[map.triangles[k][c]];
      geometry_msgs::Point p;
      p.x = v.x(), p.y = v.y(), p.z = v.z();
      m.points.push_back(p);
    }
  return m;
}

}  // namespace

visualization_msgs::MarkerArray mapMarkers(const TriangleMesh& map,
                                           const std::vector<relations::Entity>& furniture,
                                           const std::string& frame, std::size_t max_triangles) {
  visualization_msgs::MarkerArray out;
  if (!map.empty()) out.markers.push_back(meshMarker(map, frame, max_triangles));
  int id = 0;
  for (const relations::Entity& f : furniture) {
    visualization_msgs::Marker box =
        marker(frame, "furniture", id, visualization_msgs::Marker::CUBE);
    box.pose = toPose(f.box.T_world_box);
    box.scale.x = 2 * f.box.half_extents.x(), box.scale.y = 2 * f.box.half_extents.y(),
    box.scale.z = 2 * f.box.half_extents.z();
    box.color.r = 0.55f, box.color.g = 0.4f, box.color.b = 0.25f, box.color.a = 0.4f;
    out.markers.push_back(box);
    visualization_msgs::Marker name =
        marker(frame, "furniture_names", id++, visualization_msgs::Marker::TEXT_VIEW_FACING);
    name.pose.position = box.pose.position;
    name.pose.position.z += f.box.half_extents.z() + 0.05;
    name.scale.z = 0.08, name.text = f.name;
    name.color.r = name.color.g = name.color.b = name.color.a = 1.0f;
    out.markers.push_back(name);
  }
  return out;
}

}  // namespace sgt::ros
