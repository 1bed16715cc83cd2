// RGB rendering of a ray-cast camera frame: per-node albedo (objects, distractors), simple
// procedural colours for the static map (tiled floor, walls, ceiling, wooden table tops), and
// Lambert shading with an ambient term, a light from above and a weak head light. A node may
// carry a procedural pattern (simulation/appearance.hpp) that mixes its albedo with a second
// colour, or a photograph (simulation/photo_appearance.hpp) in place of its albedo.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene_graph_tracker/simulation/appearance.hpp"
#include "scene_graph_tracker/simulation/photo_appearance.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::sim {

struct RenderStyle {
  Eigen::Vector3f light_direction =
      Eigen::Vector3f(0.3f, 0.2f, 1.0f).normalized();  // towards the light, world
  float ambient = 0.35f;
  float diffuse = 0.45f;                                              // light from above
  float headlight = 0.25f;                                            // light from the camera
  Eigen::Vector3f background = Eigen::Vector3f(0.05f, 0.05f, 0.08f);  // rays that hit nothing
  float floor_tile = 0.5f;   // edge length of the floor's checker tiles (m)
  float wall_height = 3.0f;  // surfaces facing down near it are ceiling
};

struct NodeColours {
  std::unordered_map<NodeId, Eigen::Vector3f> albedo;   // RGB 0..1 per node
  std::unordered_map<NodeId, SurfacePattern> patterns;  // nodes whose albedo is patterned
  std::unordered_map<NodeId, PhotoTexture> photos;      // nodes wrapped in a photo (over both)
  NodeId static_map = kNoNode;                          // coloured by staticMapColour
};

// Albedo of the static map at a world point with a unit world normal.
Eigen::Vector3f staticMapColour(const Eigen::Vector3f& p_world, const Eigen::Vector3f& n_world,
                                const RenderStyle& style);

// The paper's five classes' colours (none for other names).
std::optional<Eigen::Vector3f> knownClassColour(const std::string& class_name);

// Default albedo of a catalog class (knownClassColour, else a colour hashed from the name).
Eigen::Vector3f classColour(const std::string& class_name);

// rgb8 image (width x height x 3, row-major) of a simulated pinhole scan from T_world_sensor.
std::vector<std::uint8_t> renderRgb(const SimulatedScan& scan,
                                    const Eigen::Isometry3d& T_world_sensor,
                                    const NodeColours& colours, const RenderStyle& style = {});

}  // namespace sgt::sim
