// Procedural single-storey lab building: the static map for tests and benchmarks. A grid of
// rooms with doors, tiled floor and ceiling, solid walls and seeded furniture that makes every
// room look different (no ambiguity for LiDAR localization). Deterministic for given options.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

struct BuildingOptions {
  float length_x = 60.0f;  // footprint [0, length_x] x [0, length_y], outer wall faces included
  float length_y = 50.0f;
  float wall_height = 3.0f;  // ceiling height
  float wall_thickness = 0.2f;
  int rooms_x = 6;
  int rooms_y = 4;
  float door_width = 1.0f;
  float door_height = 2.1f;
  // Quad edge length of the surface tessellation; only used as is when target_triangles == 0,
  // otherwise replaced by the edge length that lands the triangle count on the target.
  float tile_size = 0.25f;
  std::size_t target_triangles = 411698;  // the paper's static map
  std::uint32_t seed = 7;                 // furniture and door placement
  bool furniture = true;
};

struct Building {
  TriangleMesh mesh;
  Eigen::Vector3f workbench_top_centre;    // top surface of the workbench in room 0
  Eigen::Vector2f workbench_size;          // x, y extent of its top
  Eigen::Vector3f robot_start;             // free floor point (z = 0) ~2 m in front (+y) of it
  std::vector<Eigen::AlignedBox3f> rooms;  // free interiors, index ix + rooms_x * iy
  float tile_size = 0.0f;                  // quad edge length actually used
};

Building makeBuilding(const BuildingOptions& o = {});

}  // namespace sgt
