// Indexed triangle mesh in metres, the unit every other part of the package works in.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace sgt {

using Triangle = std::array<std::uint32_t, 3>;

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Triangle> triangles;

  std::size_t triangleCount() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }

  Eigen::AlignedBox3f boundingBox() const;
  // Largest distance between two vertices (BOP's object diameter). Exact for meshes up to 2,000
  // vertices; above that, exact over the extreme vertices along 258 directions (error < 0.01 %).
  double diameter() const;
  double surfaceArea() const;

  // Appends `other` moved by T (vertices transformed, indices shifted).
  void append(const TriangleMesh& other,
              const Eigen::Isometry3f& T = Eigen::Isometry3f::Identity());
  void transform(const Eigen::Isometry3f& T);
  void scale(float s);
};

struct SurfaceSample {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;  // unit face normals of the sampled triangles
};

// Area-weighted uniform sampling of the mesh surface; deterministic for a given seed.
SurfaceSample sampleSurface(const TriangleMesh& mesh, std::size_t count, std::uint32_t seed = 1);

}  // namespace sgt
