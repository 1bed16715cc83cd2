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

std::optional<Eigen::Vector3f> knownClassColour(const std::string& name) {
  if (name == "multimeter") return Eigen::Vector3f(0.95f, 0.78f, 0.10f);
  if (name == "screwdriver") return Eigen::Vector3f(0.85f, 0.12f, 0.10f);
  if (name == "materialbox") return Eigen::Vector3f(0.15f, 0.35f, 0.80f);
  if (name == "klt") return Eigen::Vector3f(0.30f, 0.55f, 0.75f);
  if (name == "relay") return Eigen::Vector3f(0.10f, 0.60f, 0.25f);
  return std::nullopt;
}

Eigen::Vector3f classColour(const std::string& name) {
  if (const auto known = knownClassColour(name)) return *known;
  const std::size_t h = std::hash<std::string>{}(name);
  return {0.2f + 0.6f * ((h & 0xff) / 255.0f), 0.2f + 0.6f * (((h >> 8) & 0xff) / 255.0f),
          0.2f + 0.6f * (((h >> 16) & 0xff) / 255.0f)};
}

namespace {

// What one node's surface looks like, looked up once per run of pixels of the same node.
struct NodeLook {
  Eigen::Vector3f albedo;
  const SurfacePattern* pattern = nullptr;
  const PhotoTexture* photo = nullptr;
};

NodeLook lookOf(const NodeColours& colours, NodeId node) {
  NodeLook look{Eigen::Vector3f(0.6f, 0.6f, 0.6f)};
  const auto it = colours.albedo.find(node);
  if (it != colours.albedo.end()) look.albedo = it->second;
  const auto p = colours.patterns.find(node);
  if (p != colours.patterns.end()) look.pattern = &p->second;
  const auto f = colours.photos.find(node);
  if (f != colours.photos.end() && f->second.image) look.photo = &f->second;
  return look;
}

Eigen::Vector3f albedoAt(const NodeLook& look, const Eigen::Vector3f& p_world,
                         const Eigen::Vector3f& n_world) {
  if (look.photo) return photoColour(*look.photo, p_world, n_world);
  if (!look.pattern) return look.albedo;
  const float w = patternWeight(*look.pattern, p_world);
  return (1.0f - w) * look.albedo + w * look.pattern->second;
}

}  // namespace

std::vector<std::uint8_t> renderRgb(const SimulatedScan& scan,
                                    const Eigen::Isometry3d& T_world_sensor,
                                    const NodeColours& colours, const RenderStyle& style) {
  const std::size_t n = scan.range.size();
  std::vector<std::uint8_t> rgb(3 * n);
  const Eigen::Matrix3f R = T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f t = T_world_sensor.translation().cast<float>();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        NodeId cached_node = kNoNode;  // neighbouring pixels mostly show the same node
        NodeLook look{};
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          Eigen::Vector3f c = style.background;
          const NodeId node = scan.node[i];
          if (node != kNoNode) {
            const Eigen::Vector3f n_world = R * scan.normals[i];  // faces the camera
            const Eigen::Vector3f p_world = R * scan.points[i] + t;
            Eigen::Vector3f albedo;
            if (node == colours.static_map) {
              albedo = staticMapColour(p_world, n_world, style);
            } else {
              if (node != cached_node) look = lookOf(colours, node), cached_node = node;
              albedo = albedoAt(look, p_world, n_world);
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
