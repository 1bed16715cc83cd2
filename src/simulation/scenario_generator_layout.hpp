// Internal to the scenario generator: footprints on the bench, keyframe interpolation, and the
// per-object plan (where it rests, what supports it when) that the relations are written from.
#pragma once

#include <Eigen/Geometry>
#include <random>
#include <string>
#include <vector>

#include "scene_graph_tracker/simulation/scenario_generator.hpp"

namespace sgt::sim::gen {

// The generated building's workbench top: 1.6 m x 0.8 m, 0.75 m above the floor (workbench frame:
// origin at the top's centre).
constexpr double kBenchHalfX = 0.8, kBenchHalfY = 0.4, kFloorZ = -0.75;
// Where footprints may lie: inside the bench, and inside what the camera sees from the front.
constexpr double kUsableHalfX = 0.7, kUsableHalfY = 0.34;
// Camera optical centre above the floor and ahead of base_link (the demo's Tiago head mount).
constexpr double kEyeHeight = 1.25, kEyeForward = 0.10;

// An oriented rectangle on the bench.
struct Footprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d half = Eigen::Vector2d::Zero();
  double yaw = 0.0;  // rad
};
bool overlaps(const Footprint& a, const Footprint& b, double margin);
bool insideUsableArea(const Footprint& f);

// One thing supporting an object over [from, to): "on workbench", "on multimeter_1", "in klt_1".
struct SupportSpan {
  relations::Relation relation = relations::Relation::On;
  std::string object;
  double from = 0.0;
  double to = std::numeric_limits<double>::infinity();
};

struct PlannedObject {
  std::string id, class_name;
  std::vector<GeneratedKey> keys;  // the first key is at t = 0
  std::vector<SupportSpan> supports;
  bool fixed = false;  // part of a stack or a container with contents: never moved
  bool busy = false;   // already has a manipulation
  bool holds = false;  // something rests on or in it
};

// Pose at time t, keys interpolated linearly (yaw too: keys never turn by more than 180 deg).
GeneratedKey poseAt(const std::vector<GeneratedKey>& keys, double t);

double uniform(std::mt19937& rng, double lo, double hi);
int uniformInt(std::mt19937& rng, int lo, int hi);  // [lo, hi]
bool chance(std::mt19937& rng, double p);

}  // namespace sgt::sim::gen
