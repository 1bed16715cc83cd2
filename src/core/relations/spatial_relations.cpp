#include "scene_graph_tracker/relations/spatial_relations.hpp"

#include <cmath>

namespace sgt::relations {
namespace {

constexpr const char* kNames[kRelationCount] = {"on",          "in",     "left_of", "right_of",
                                                "in_front_of", "behind", "above",   "below"};

// The side's axis (0 x, 1 y, 2 z) and direction (+1 / -1) in R's frame.
int axisOf(Side s) {
  switch (s) {
    case Side::Front:
    case Side::Back:
      return 0;
    case Side::Left:
    case Side::Right:
      return 1;
    default:
      return 2;
  }
}
double signOf(Side s) { return s == Side::Front || s == Side::Left || s == Side::Top ? 1.0 : -1.0; }

// R's box extruded outward from the face toward `side` by o * e, and widened by `widen` * o * e
// on both ends of the other two axes (0: projection, 1: halfspace).
OrientedBox extrusion(const OrientedBox& r, Side side, const RelationOptions& o, double widen) {
  const int a = axisOf(side);
  const Eigen::Vector3d e = 2.0 * r.half_extents;
  Eigen::Vector3d half = r.half_extents + widen * o.factor * e;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  half[a] = 0.5 * o.factor * e[a];
  centre[a] = signOf(side) * (r.half_extents[a] + half[a]);
  OrientedBox out;
  out.T_world_box = r.T_world_box * Eigen::Translation3d(centre);
  out.half_extents = half;
  return out;
}

}  // namespace

const char* relationName(Relation r) { return kNames[static_cast<int>(r)]; }

std::optional<Relation> parseRelation(const std::string& name) {
  for (int k = 0; k < kRelationCount; ++k)
    if (name == kNames[k]) return static_cast<Relation>(k);
  return std::nullopt;
}

bool isDirectional(Relation r) { return r != Relation::On && r != Relation::In; }

const char* sideName(Side s) {
  constexpr const char* names[] = {"front", "back", "left", "right", "top", "bottom"};
  return names[static_cast<int>(s)];
}

Side sideOf(Relation r) {
  switch (r) {
    case Relation::LeftOf:
      return Side::Left;
    case Relation::RightOf:
      return Side::Right;
    case Relation::InFrontOf:
      return Side::Front;
    case Relation::Behind:
      return Side::Back;
    case Relation::Below:
      return Side::Bottom;
    default:
      return Side::Top;
  }
}

Solid solidOf(Relation r, Mode m) {
  if (r == Relation::In) return Solid::Box;
  if (r == Relation::On || m == Mode::Strict) return Solid::Projection;
  return Solid::Halfspace;
}

OrientedBox projection(const OrientedBox& reference, Side side, const RelationOptions& o) {
  return extrusion(reference, side, o, 0.0);
}

OrientedBox halfspace(const OrientedBox& reference, Side side, const RelationOptions& o) {
  return extrusion(reference, side, o, 1.0);
}

bool holds(Relation r, Mode m, const OrientedBox& target, const OrientedBox& reference,
           const RelationOptions& o) {
  const bool strict = m == Mode::Strict;
  switch (solidOf(r, m)) {
    case Solid::Box:
      return contains(reference, target, o.tolerance) || (!strict && intersects(reference, target));
    case Solid::Halfspace:
      return intersects(halfspace(reference, sideOf(r), o), target);
    case Solid::Projection:
      break;
  }
  const OrientedBox p = projection(reference, sideOf(r), o);
  const bool in_solid = strict ? contains(p, target, o.tolerance) : intersects(p, target);
  if (r != Relation::On) return in_solid;
  return in_solid && distance(target, reference) < o.on_max_distance;
}

OrientedBox viewerAligned(const OrientedBox& reference, const Eigen::Isometry3d& T_world_camera,
                          const Eigen::Vector3d& forward_in_camera) {
  const Eigen::Vector3d f = T_world_camera.linear() * forward_in_camera;
  const double yaw = std::atan2(f.y(), f.x());  // a camera looking straight down keeps some yaw
  return enclosingBox(reference,
                      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix());
}

bool holdsFromViewpoint(Relation r, Mode m, const OrientedBox& target, const OrientedBox& reference,
                        const Eigen::Isometry3d& T_world_camera, const RelationOptions& o,
                        const Eigen::Vector3d& forward_in_camera) {
  if (!isDirectional(r)) return holds(r, m, target, reference, o);
  // The viewer frame's +x points away from the viewer: "in front of R" is R's -x side.
  if (r == Relation::InFrontOf)
    r = Relation::Behind;
  else if (r == Relation::Behind)
    r = Relation::InFrontOf;
  return holds(r, m, target, viewerAligned(reference, T_world_camera, forward_in_camera), o);
}

}  // namespace sgt::relations
