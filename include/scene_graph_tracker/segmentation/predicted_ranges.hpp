// What the scene predicts along every ray of a measurement set (its range and node), for
// pre-segmentation, which compares each measurement with it.
//
// Casting every ray of a 640 x 480 depth image into the building costs as much as refining all
// objects. Most of such an image sees large planes of the static map (floor, walls, the bench
// top), where a ray's predicted range follows from its neighbours'. So on a depth image's grid of
// rays from one centre, rays are cast every 4th pixel in x and y first. A block of 4 x 4 pixels
// whose four corner rays hit the static map on one plane, and whose rays cannot meet the box of an
// enabled object instance, takes its other rays' ranges from that plane; one whose corners hit
// nothing (beyond a map's edge) predicts no hit; every other ray is cast.
// Seen from one centre, the rays between four corner rays meet the corners' plane inside the
// corners' quadrilateral, so the plane's range is the scene's unless a part of the map smaller than
// the block stands in front of that plane between the corners. A spinning LiDAR's blocks are too
// coarse for that (4 rings of a VLP-16 span 8 deg: a bench between two rings' hits on the floor):
// other sensors, and from_planes off, cast every ray. A range outside the rays' limits is no hit,
// as a cast's is.
#pragma once

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

// Writes range and node of every ray of `m` into `hits` (resized to the grid); returns the number
// of rays cast.
std::size_t predictRanges(const RaycastScene& scene, const RangeMeasurements& m, RayHits& hits,
                          bool from_planes);

}  // namespace sgt
