#include "scene_graph_tracker/geometry/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace sgt {
namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

std::uint32_t addVertex(TriangleMesh& mesh, const Eigen::Vector3f& v) {
  mesh.vertices.push_back(v);
  return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
}

// Appends the selected faces of `box`; segments(edge_length) gives the quads along an edge.
template <typename Segments>
void appendBoxFaces(TriangleMesh& mesh, const Eigen::AlignedBox3f& box, std::uint8_t faces,
                    bool inward, Segments segments) {
  const Eigen::Vector3f lo = box.min(), d = box.sizes();
  const Eigen::Vector3f dx(d.x(), 0, 0), dy(0, d.y(), 0), dz(0, 0, d.z());
  struct Face {
    std::uint8_t bit;
    Eigen::Vector3f corner, u, v;  // outward normal = u x v
  };
  const Face all[6] = {
      {kFaceNegX, lo, dz, dy},      {kFacePosX, lo + dx, dy, dz}, {kFaceNegY, lo, dx, dz},
      {kFacePosY, lo + dy, dz, dx}, {kFaceNegZ, lo, dy, dx},      {kFacePosZ, lo + dz, dx, dy},
  };
  for (const Face& f : all) {
    if (!(faces & f.bit)) continue;
    const float lu = f.u.norm(), lv = f.v.norm();
    if (!(lu > 0.0f) || !(lv > 0.0f)) continue;  // flat box: this face has no area
    if (inward)
      appendQuadGrid(mesh, f.corner, f.v, f.u, segments(lv), segments(lu));
    else
      appendQuadGrid(mesh, f.corner, f.u, f.v, segments(lu), segments(lv));
  }
}

// Ring of `segments` vertices of radius r at height z, counter-clockwise seen from +z.
std::uint32_t addRing(TriangleMesh& mesh, float r, float z, int segments) {
  const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int i = 0; i < segments; ++i) {
    const float a = kTwoPi * static_cast<float>(i) / static_cast<float>(segments);
    mesh.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  return first;
}

// Quads between ring `lower` and ring `upper` (both counter-clockwise), normals pointing away
// from the axis.
void bridgeRings(TriangleMesh& mesh, std::uint32_t lower, std::uint32_t upper, int segments) {
  for (int i = 0; i < segments; ++i) {
    const std::uint32_t i0 = static_cast<std::uint32_t>(i);
    const std::uint32_t i1 = static_cast<std::uint32_t>((i + 1) % segments);
    mesh.triangles.push_back({lower + i0, lower + i1, upper + i1});
    mesh.triangles.push_back({lower + i0, upper + i1, upper + i0});
  }
}

// Fan from `apex` to a counter-clockwise ring; `up` selects a normal towards +z.
void fan(TriangleMesh& mesh, std::uint32_t apex, std::uint32_t ring, int segments, bool up) {
  for (int i = 0; i < segments; ++i) {
    const std::uint32_t a = ring + static_cast<std::uint32_t>(i);
    const std::uint32_t b = ring + static_cast<std::uint32_t>((i + 1) % segments);
    if (up)
      mesh.triangles.push_back({apex, a, b});
    else
      mesh.triangles.push_back({apex, b, a});
  }
}

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

void splitAllInFour(TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
  midpoints.reserve(mesh.triangles.size() * 2);
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto it = midpoints.emplace(edgeKey(a, b), 0u);
    if (it.second) it.first->second = addVertex(mesh, 0.5f * (mesh.vertices[a] + mesh.vertices[b]));
    return it.first->second;
  };
  std::vector<Triangle> out;
  out.reserve(mesh.triangles.size() * 4);
  for (const Triangle& t : mesh.triangles) {
    const std::uint32_t m01 = midpoint(t[0], t[1]), m12 = midpoint(t[1], t[2]),
                        m20 = midpoint(t[2], t[0]);
    out.push_back({t[0], m01, m20});
    out.push_back({m01, t[1], m12});
    out.push_back({m20, m12, t[2]});
    out.push_back({m01, m12, m20});
  }
  mesh.triangles.swap(out);
}

// One pass of conforming longest-edge bisection over the largest triangles, each triangle split
// at most once, stopping as soon as the mesh has `target` triangles.
void bisectLargest(TriangleMesh& mesh, std::size_t target) {
  const std::size_t n = mesh.triangles.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (edge key, triangle)
  edges.reserve(3 * n);
  std::vector<float> longest(n);
  std::vector<int> longest_edge(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Triangle& t = mesh.triangles[i];
    longest[i] = -1.0f;
    for (int e = 0; e < 3; ++e) {
      edges.emplace_back(edgeKey(t[e], t[(e + 1) % 3]), static_cast<std::uint32_t>(i));
      const float len = (mesh.vertices[t[e]] - mesh.vertices[t[(e + 1) % 3]]).squaredNorm();
      if (len > longest[i]) longest[i] = len, longest_edge[i] = e;
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return longest[a] > longest[b]; });
  std::vector<bool> touched(n, false);
  for (std::uint32_t i : order) {
    if (mesh.triangles.size() >= target) return;
    if (touched[i]) continue;
    const Triangle t = mesh.triangles[i];
    const std::uint32_t a = t[longest_edge[i]], b = t[(longest_edge[i] + 1) % 3];
    const std::uint64_t key = edgeKey(a, b);
    const auto range =
        std::equal_range(edges.begin(), edges.end(), std::make_pair(key, 0u),
                         [](const auto& x, const auto& y) { return x.first < y.first; });
    bool free = true;
    for (auto it = range.first; it != range.second; ++it) free = free && !touched[it->second];
    if (!free) continue;
    const std::uint32_t m = addVertex(mesh, 0.5f * (mesh.vertices[a] + mesh.vertices[b]));
    for (auto it = range.first; it != range.second; ++it) {
      Triangle& s = mesh.triangles[it->second];
      touched[it->second] = true;
      int e = 0;  // rotate so the split edge is (s[e], s[e+1])
      while (edgeKey(s[e], s[(e + 1) % 3]) != key) ++e;
      const Triangle old = s;
      s = {old[e], m, old[(e + 2) % 3]};
      mesh.triangles.push_back({m, old[(e + 1) % 3], old[(e + 2) % 3]});
    }
  }
}

}  // namespace

void appendQuadGrid(TriangleMesh& mesh, const Eigen::Vector3f& corner, const Eigen::Vector3f& u,
                    const Eigen::Vector3f& v, int nu, int nv) {
  nu = std::max(nu, 1);
  nv = std::max(nv, 1);
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      mesh.vertices.push_back(corner + u * (static_cast<float>(i) / nu) +
                              v * (static_cast<float>(j) / nv));
  const auto row = static_cast<std::uint32_t>(nu + 1);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t p = base + static_cast<std::uint32_t>(j) * row + i;
      mesh.triangles.push_back({p, p + 1, p + row + 1});
      mesh.triangles.push_back({p, p + row + 1, p + row});
    }
  }
}

void appendBox(TriangleMesh& mesh, const Eigen::AlignedBox3f& box, float max_edge,
               std::uint8_t faces, bool inward) {
  appendBoxFaces(mesh, box, faces, inward, [max_edge](float len) {
    return max_edge > 0.0f ? std::max(1, static_cast<int>(std::lround(len / max_edge))) : 1;
  });
}

TriangleMesh makeBox(const Eigen::Vector3f& size, int subdivisions) {
  TriangleMesh mesh;
  const int n = std::max(subdivisions, 1);
  appendBoxFaces(mesh, Eigen::AlignedBox3f(-0.5f * size, 0.5f * size), kAllFaces, false,
                 [n](float) { return n; });
  return mesh;
}

TriangleMesh makeCylinder(float radius, float length, int segments, bool capped) {
  TriangleMesh mesh;
  segments = std::max(segments, 3);
  const std::uint32_t bottom = addRing(mesh, radius, -0.5f * length, segments);
  const std::uint32_t top = addRing(mesh, radius, 0.5f * length, segments);
  bridgeRings(mesh, bottom, top, segments);
  if (capped) {
    fan(mesh, addVertex(mesh, Eigen::Vector3f(0, 0, -0.5f * length)), bottom, segments, false);
    fan(mesh, addVertex(mesh, Eigen::Vector3f(0, 0, 0.5f * length)), top, segments, true);
  }
  return mesh;
}

TriangleMesh makeSphere(float radius, int segments, int rings) {
  TriangleMesh mesh;
  segments = std::max(segments, 3);
  rings = std::max(rings, 2);
  // Latitude rings k = 1 .. rings-1 from the north pole down; the poles are single vertices.
  std::vector<std::uint32_t> ring_start;
  for (int k = 1; k < rings; ++k) {
    const float polar = 0.5f * kTwoPi * static_cast<float>(k) / static_cast<float>(rings);
    ring_start.push_back(
        addRing(mesh, radius * std::sin(polar), radius * std::cos(polar), segments));
  }
  for (std::size_t k = 0; k + 1 < ring_start.size(); ++k)
    bridgeRings(mesh, ring_start[k + 1], ring_start[k], segments);
  fan(mesh, addVertex(mesh, Eigen::Vector3f(0, 0, radius)), ring_start.front(), segments, true);
  fan(mesh, addVertex(mesh, Eigen::Vector3f(0, 0, -radius)), ring_start.back(), segments, false);
  return mesh;
}

TriangleMesh makeOpenBox(const Eigen::Vector3f& outer, float wall, int subdivisions) {
  TriangleMesh mesh;
  const int n = std::max(subdivisions, 1);
  auto fixed = [n](float) { return n; };
  const Eigen::Vector3f h = 0.5f * outer;
  const Eigen::Vector2f in = h.head<2>() - Eigen::Vector2f::Constant(wall);  // inner half-size
  // Outside: bottom and the four walls.
  appendBoxFaces(mesh, Eigen::AlignedBox3f(-h, h), kAllFaces & ~kFacePosZ, false, fixed);
  // Cavity: inner floor and inner walls, facing into the cavity.
  const Eigen::AlignedBox3f cavity(Eigen::Vector3f(-in.x(), -in.y(), -h.z() + wall),
                                   Eigen::Vector3f(in.x(), in.y(), h.z()));
  appendBoxFaces(mesh, cavity, kAllFaces & ~kFacePosZ, true, fixed);
  // Rim at the top: two strips along x over the full length, two along y between them.
  const Eigen::Vector3f ex(1, 0, 0), ey(0, 1, 0);
  appendQuadGrid(mesh, Eigen::Vector3f(-h.x(), -h.y(), h.z()), 2 * h.x() * ex, wall * ey, n, 1);
  appendQuadGrid(mesh, Eigen::Vector3f(-h.x(), in.y(), h.z()), 2 * h.x() * ex, wall * ey, n, 1);
  appendQuadGrid(mesh, Eigen::Vector3f(-h.x(), -in.y(), h.z()), wall * ex, 2 * in.y() * ey, 1, n);
  appendQuadGrid(mesh, Eigen::Vector3f(in.x(), -in.y(), h.z()), wall * ex, 2 * in.y() * ey, 1, n);
  return mesh;
}

void subdivideToAtLeast(TriangleMesh& mesh, std::size_t min_triangles) {
  if (mesh.empty()) return;
  while (mesh.triangles.size() * 4 <= min_triangles) splitAllInFour(mesh);
  while (mesh.triangles.size() < min_triangles) bisectLargest(mesh, min_triangles);
}

}  // namespace sgt
