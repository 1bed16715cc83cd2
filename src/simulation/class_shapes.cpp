// What the scenario generator knows of each class: its box, and whether it is a container, found
// by casting rays into its mesh (no class names in code).
#include <algorithm>
#include <cmath>
#include <memory>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/simulation/scenario_generator.hpp"

namespace sgt::sim {
namespace {

constexpr NodeId kMeshNode = 1;

// Heights of the first surface hit by vertical rays over the middle third of the footprint.
std::vector<float> downwardHits(const RaycastScene& scene, const ClassShape& s) {
  std::vector<WorldRay> rays;
  const Eigen::Vector2d centre = 0.5 * (s.box_min + s.box_max).head<2>();
  const Eigen::Vector2d half = s.halfFootprint() / 3.0;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) {
      const Eigen::Vector2d xy = centre + Eigen::Vector2d(half.x() * i / 2.0, half.y() * j / 2.0);
      const Eigen::Vector3f origin(static_cast<float>(xy.x()), static_cast<float>(xy.y()),
                                   static_cast<float>(s.box_max.z() + 0.05));
      rays.push_back({origin, -Eigen::Vector3f::UnitZ(), static_cast<float>(s.height() + 0.1)});
    }
  RayHits hits;
  scene.cast(rays, hits);
  std::vector<float> z;
  for (std::size_t i = 0; i < rays.size(); ++i)
    z.push_back(std::isfinite(hits.range[i]) ? hits.point[i].z()
                                             : static_cast<float>(s.box_min.z()));
  return z;
}

// Distance from a point above the floor to the nearest wall along +-axis (the box edge when open).
double wallDistance(const RaycastScene& scene, const Eigen::Vector3f& origin, int axis,
                    const ClassShape& s) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const float sign : {1.0f, -1.0f}) {
    Eigen::Vector3f direction = Eigen::Vector3f::Zero();
    direction[axis] = sign;
    RayHits hits;
    scene.cast({{origin, direction, static_cast<float>(s.box_max[axis] - s.box_min[axis])}}, hits);
    const double edge = sign > 0 ? s.box_max[axis] - origin[axis] : origin[axis] - s.box_min[axis];
    nearest = std::min(nearest, std::isfinite(hits.range[0]) ? double(hits.range[0]) : edge);
  }
  return nearest;
}

ClassShape shapeOf(const ObjectClass& c) {
  ClassShape s;
  s.name = c.name;
  s.box_min = c.box.min().cast<double>();
  s.box_max = c.box.max().cast<double>();
  RaycastScene scene;
  scene.addInstance(kMeshNode, scene.addMesh(c.mesh), Eigen::Isometry3d::Identity());
  scene.commit();
  std::vector<float> z = downwardHits(scene, s);
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  const double floor = z[z.size() / 2];
  if (floor > s.box_min.z() + 0.5 * s.height()) return s;
  const Eigen::Vector2d centre = 0.5 * (s.box_min + s.box_max).head<2>();
  const Eigen::Vector3f probe(static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                              static_cast<float>(floor + 0.25 * (s.box_max.z() - floor)));
  s.container = true;
  s.floor = floor;
  s.inner_half = {wallDistance(scene, probe, 0, s), wallDistance(scene, probe, 1, s)};
  return s;
}

}  // namespace

std::map<std::string, ClassShape> classShapes(const ObjectCatalog& catalog) {
  std::map<std::string, ClassShape> shapes;
  for (const std::string& name : catalog.names()) shapes[name] = shapeOf(catalog.get(name));
  return shapes;
}

}  // namespace sgt::sim
