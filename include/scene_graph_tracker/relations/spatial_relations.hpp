// Qualitative spatial relations between oriented boxes with SEMAP's semantics (hdeeken/semap:
// PostGIS + SFCGAL over objects' bounding boxes; reference.md "Relations with SEMAP's semantics").
//
// "T r R" asks whether the target T stands in relation r to the reference R. Directions are taken
// in R's own frame: front +x, back -x, left +y, right -y, top +z, bottom -z. With R's full extents
// e = 2 * half_extents and the factor o (3.5):
//   projection(R, side): R's cross-section extruded outward from that face by o * e along the
//                        side's axis (SEMAP's create_extrusions "_p" solids);
//   halfspace(R, side):  the same, also widened by o * e on both ends of the two other axes
//                        (SEMAP's "_hs" solids).
// Which solid and which test each relation uses:
//   left_of / right_of / in_front_of / behind / above / below
//        strict:  projection(R, side) contains T's box
//        relaxed: halfspace(R, side) intersects T's box
//        (side: left_of Left, right_of Right, in_front_of Front, behind Back, above Top, below
//        Bottom)
//   on   strict:  projection(R, Top) contains T  AND  distance(T, R) < on_max_distance
//        relaxed: projection(R, Top) intersects T AND distance(T, R) < on_max_distance
//   in   strict:  R contains T;  relaxed: R contains or intersects T
// Containment takes RelationOptions::tolerance (0 = SEMAP's exact test); a tracker with pose
// noise sets a few mm so an object resting on a table whose pose sinks 1 mm into it stays "on".
//
// Camera-relative directions (people say "left" from where they stand): holdsFromViewpoint()
// takes the directional relations in a viewer frame instead of R's own frame: centred at R,
// z up, x along the camera's horizontal viewing direction (its yaw), y to the camera's left;
// R's extents are those of the smallest box in that frame enclosing R. left_of / right_of are the
// viewer's left and right; in_front_of means between R and the viewer (the -x side) and behind
// beyond R (+x); above / below / on / in are unchanged (on / in always use R's own box).
//
// Support by rays (objects that are not boxes, e.g. a relay resting on the floor of a hollow
// KLT): relations/support_rays.hpp.
#pragma once

#include <optional>
#include <string>

#include "scene_graph_tracker/relations/oriented_box.hpp"

namespace sgt::relations {

enum class Relation { On, In, LeftOf, RightOf, InFrontOf, Behind, Above, Below };
enum class Mode { Strict, Relaxed };
constexpr int kRelationCount = 8;

// "on", "in", "left_of", "right_of", "in_front_of", "behind", "above", "below"
// (msg/SceneGraphEdge.msg).
const char* relationName(Relation r);
std::optional<Relation> parseRelation(const std::string& name);
bool isDirectional(Relation r);  // all but on and in

struct RelationOptions {
  double factor = 3.5;            // extrusion factor o
  double on_max_distance = 0.02;  // m, "on": 3D distance between the boxes below this
  double tolerance = 0.0;  // m, corners may lie this far outside a solid that must contain them
};

enum class Side { Front, Back, Left, Right, Top, Bottom };
const char* sideName(Side s);
// The side of R a directional relation looks toward (Top for on, in has none: returns Top).
Side sideOf(Relation r);

enum class Solid { Projection, Halfspace, Box };
// The solid of R that `holds` tests T against (see the table above).
Solid solidOf(Relation r, Mode m);

// Does `target` stand in relation `r` to `reference` (T r R)?
bool holds(Relation r, Mode m, const OrientedBox& target, const OrientedBox& reference,
           const RelationOptions& o = {});

// The extrusion solids, as oriented boxes in R's orientation.
OrientedBox projection(const OrientedBox& reference, Side side, const RelationOptions& o = {});
OrientedBox halfspace(const OrientedBox& reference, Side side, const RelationOptions& o = {});

// R re-expressed in the viewer frame described above (camera optical frame: z forward).
OrientedBox viewerAligned(const OrientedBox& reference, const Eigen::Isometry3d& T_world_camera,
                          const Eigen::Vector3d& forward_in_camera = Eigen::Vector3d::UnitZ());
// `holds` with the directional relations taken from the camera's point of view (see above).
bool holdsFromViewpoint(Relation r, Mode m, const OrientedBox& target, const OrientedBox& reference,
                        const Eigen::Isometry3d& T_world_camera, const RelationOptions& o = {},
                        const Eigen::Vector3d& forward_in_camera = Eigen::Vector3d::UnitZ());

}  // namespace sgt::relations
