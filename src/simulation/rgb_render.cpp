#include "scene_graph_tracker/simulation/rgb_render.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace sgt::sim {

Eigen::Vector3f staticMapColour(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                                const RenderStyle& style) {
  if (n.z() > 0.9f) {
    if (p.z() < 0.05f) {  // floor: grey checker tiles
      const auto ix = static_cast<long>(std::floor(p.x() / style.floor_tile));
      const auto iy = static_cast<long>(std::floor(p.y() / style.floor_tile));
      return ((ix + iy) & 1) ? Eigen::Vector3f(0.52f, 0.52f, 0.50f)
                             : Eigen::Vector3f(0.62f, 0.61f, 0.58f);
    }
    return Eigen::Vector3f(0.62f, 0.45f, 0.28f);  // table and shelf tops: wood
  }
  if (n.z() < -0.9f)
    return p.z() > style.wall_height - 0.05f ? Eigen::Vector3f(0.92f, 0.92f, 0.90f)   // ceiling
                                             : Eigen::Vector3f(0.35f, 0.30f, 0.25f);  // undersides
  if (p.z() < 0.1f) return Eigen::Vector3f(0.30f, 0.30f, 0.32f);                      // skirting
  return Eigen::Vector3f(0.84f, 0.81f, 0.74f);  // walls, furniture sides
}

Eigen::Vector3f classColour(const std::string& name) {
  if (name == "multimeter") return {0.95f, 0.78f, 0.10f};
  if (name == "screwdriver") return {0.85f, 0.12f, 0.10f};
  if (name == "materialbox") return {0.15f, 0.35f, 0.80f};
  if (name == "klt") return {0.30f, 0.55f, 0.75f};
  if (name == "relay") return {0.10f, 0.60f, 0.25f};
  const std::size_t h = std::hash<std::string>{}(name);
  return {0.2f + 0.6f * ((h & 0xff) / 255.0f), 0.2f + 0.6f * (((h >> 8) & 0xff) / 255.0f),
          0.2f + 0.6f * (((h >> 16) & 0xff) / 255.0f)};
}

std::vector<std::uint8_t> renderRgb(const SimulatedScan& scan,
                                    const Eigen::Isometry3d& T_world_sensor,
                                    const NodeColours& colours, const RenderStyle& style) {
  const std::size_t n = scan.range.size();
  std::vector<std::uint8_t> rgb(3 * n);
  const Eigen::Matrix3f R = T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f t = T_world_sensor.translation().cast<float>();
  const Eigen::Vector3f fallback(0.6f, 0.6f, 0.6f);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        NodeId cached_node = kNoNode;  // neighbouring pixels mostly show the same node
        Eigen::Vector3f cached = fallback;
        const SurfacePattern* pattern = nullptr;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          Eigen::Vector3f c = style.background;
          const NodeId node = scan.node[i];
          if (node != kNoNode) {
            const Eigen::Vector3f n_world = R * scan.normals[i];  // faces the camera
            Eigen::Vector3f albedo;
            if (node == colours.static_map) {
              albedo = staticMapColour(R * scan.points[i] + t, n_world, style);
            } else {
              if (node != cached_node) {
                const auto it = colours.albedo.find(node);
                cached = it != colours.albedo.end() ? it->second : fallback;
                const auto p = colours.patterns.find(node);
                pattern = p != colours.patterns.end() ? &p->second : nullptr;
                cached_node = node;
              }
              albedo = cached;
              if (pattern) {
                const float w = patternWeight(*pattern, R * scan.points[i] + t);
                albedo = (1.0f - w) * albedo + w * pattern->second;
              }
            }
            const float range = scan.range[i];
            const float head =
                range > 0.0f ? std::abs(scan.normals[i].dot(scan.points[i])) / range : 0.0f;
            const float shade = style.ambient +
                                style.diffuse * std::max(0.0f, n_world.dot(style.light_direction)) +
                                style.headlight * head;
            c = albedo * shade;
          }
          for (int k = 0; k < 3; ++k)
            rgb[3 * i + k] =
                static_cast<std::uint8_t>(std::clamp(c[k] * 255.0f + 0.5f, 0.0f, 255.0f));
        }
      });
  return rgb;
}

}  // namespace sgt::sim
