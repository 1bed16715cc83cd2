// Tessellated primitive solids (box, cylinder, sphere, open crate) and uniform mesh refinement.
// Every surface is wound counter-clockwise seen from outside, so face normals point outwards,
// and no primitive emits a zero-area triangle.
#pragma once

#include <cstdint>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

// Box of the given edge lengths centred at the origin; each face is split into
// subdivisions x subdivisions quads (two triangles each).
TriangleMesh makeBox(const Eigen::Vector3f& size, int subdivisions = 1);

// Cylinder along z centred at the origin; `capped` adds triangle fans at both ends.
TriangleMesh makeCylinder(float radius, float length, int segments = 32, bool capped = true);

// UV sphere centred at the origin; the poles are closed by triangle fans (no degenerate slivers).
TriangleMesh makeSphere(float radius, int segments = 32, int rings = 16);

// Hollow crate open at +z: bottom and four walls of thickness `wall`, with outer, inner and rim
// surfaces (closed surface). Outer extents `outer`, centred at the origin.
TriangleMesh makeOpenBox(const Eigen::Vector3f& outer, float wall, int subdivisions = 1);

// Refines until the mesh has at least `min_triangles` triangles (no-op if it already has):
// splits every triangle into four through its edge midpoints (shared midpoints are reused) while
// that does not overshoot, then bisects the longest edges of the largest triangles (splitting
// both triangles sharing an edge) until the count is reached, so it ends within a few triangles
// of the target. Winding is preserved.
void subdivideToAtLeast(TriangleMesh& mesh, std::size_t min_triangles);

// Building blocks for composite models.
// Appends a planar grid of nu x nv quads spanning corner + [0,1]*u + [0,1]*v; normal is u x v.
void appendQuadGrid(TriangleMesh& mesh, const Eigen::Vector3f& corner, const Eigen::Vector3f& u,
                    const Eigen::Vector3f& v, int nu, int nv);

// Face selection bits for appendBox.
enum BoxFace : std::uint8_t {
  kFaceNegX = 1,
  kFacePosX = 2,
  kFaceNegY = 4,
  kFacePosY = 8,
  kFaceNegZ = 16,
  kFacePosZ = 32,
  kAllFaces = 63,
};

// Appends the selected faces of an axis-aligned box, each tessellated into quads with edges of
// about `max_edge` (at least one quad per face). `inward` flips the winding (a cavity's walls).
void appendBox(TriangleMesh& mesh, const Eigen::AlignedBox3f& box, float max_edge,
               std::uint8_t faces = kAllFaces, bool inward = false);

}  // namespace sgt
