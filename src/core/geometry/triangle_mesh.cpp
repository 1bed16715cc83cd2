#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace sgt {

Eigen::AlignedBox3f TriangleMesh::boundingBox() const {
  Eigen::AlignedBox3f box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

namespace {
double maxPairDistance(const std::vector<Eigen::Vector3f>& pts) {
  double best = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = i + 1; j < pts.size(); ++j)
      best = std::max(best, static_cast<double>((pts[i] - pts[j]).squaredNorm()));
  return std::sqrt(best);
}
}  // namespace

double TriangleMesh::diameter() const {
  if (vertices.size() <= 2000) return maxPairDistance(vertices);
  // Extreme vertices along a fibonacci sphere of directions; the diameter's endpoints are
  // extreme along the direction joining them, and nearby directions find them.
  const int n_dirs = 258;
  std::vector<Eigen::Vector3f> extremes;
  extremes.reserve(n_dirs);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n_dirs; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / n_dirs;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3f d(r * std::cos(golden * k), r * std::sin(golden * k), z);
    std::size_t arg = 0;
    float best = -std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const float p = d.dot(vertices[i]);
      if (p > best) best = p, arg = i;
    }
    extremes.push_back(vertices[arg]);
  }
  return maxPairDistance(extremes);
}

double TriangleMesh::surfaceArea() const {
  double area = 0.0;
  for (const auto& t : triangles)
    area += 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
  return area;
}

void TriangleMesh::append(const TriangleMesh& other, const Eigen::Isometry3f& T) {
  const auto offset = static_cast<std::uint32_t>(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices) vertices.push_back(T * v);
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

void TriangleMesh::transform(const Eigen::Isometry3f& T) {
  for (auto& v : vertices) v = T * v;
}

void TriangleMesh::scale(float s) {
  for (auto& v : vertices) v *= s;
}

SurfaceSample sampleSurface(const TriangleMesh& mesh, std::size_t count, std::uint32_t seed) {
  SurfaceSample out;
  if (mesh.empty() || count == 0) return out;
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0.0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    total += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                       .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                       .norm();
    cumulative[i] = total;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  out.points.reserve(count);
  out.normals.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double pick = uni(rng) * total;
    const std::size_t i = static_cast<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const auto& t = mesh.triangles[std::min(i, mesh.triangles.size() - 1)];
    double a = uni(rng), b = uni(rng);
    if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
    const Eigen::Vector3f& p0 = mesh.vertices[t[0]];
    const Eigen::Vector3f e1 = mesh.vertices[t[1]] - p0, e2 = mesh.vertices[t[2]] - p0;
    out.points.push_back(p0 + static_cast<float>(a) * e1 + static_cast<float>(b) * e2);
    out.normals.push_back(e1.cross(e2).normalized());
  }
  return out;
}

}  // namespace sgt
