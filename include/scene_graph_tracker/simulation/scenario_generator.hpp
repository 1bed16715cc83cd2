// Generated scenarios for the suite (`generate_scenarios`, `make suite`): many workbench scenes
// unlike the demo, each with its ground-truth relations.
//
// A scenario is drawn from one seed. It varies the number of objects (3-10, up to 4 of a class,
// same-class parts side by side), their layout on the workbench (the generated building's one
// known surface), stacks (same class and mixed), objects put into containers and taken out,
// objects carried across the bench or out of view and back at up to 1 m/s, unknown occluders
// (boards, people, boxes) hiding 30-100 % of the objects for 0.5-5 s, the robot's path
// (approach, sideways moves, turning away and back), the odometry's start error (up to 40 cm /
// 8 deg), depth noise (1-3x the demo's) and the simulated detector's misses (up to 20 %) and
// false positives (up to 0.3 per frame).
//
// Nothing about the classes is hard-coded: their sizes come from the catalog's meshes, and which
// of them are containers (and where their floor and walls are) is found by casting rays into the
// mesh (classShapes()).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"

namespace sgt::sim {

// What the generator needs to know of a class, in its object frame (metres).
struct ClassShape {
  std::string name;
  Eigen::Vector3d box_min, box_max;  // the mesh's bounding box
  // A container: a vertical ray through the middle of its footprint first hits a floor in its
  // lower half. Then `floor` is that floor's height and `inner_half` the half extents (x, y) of
  // the free space above it, measured by horizontal rays to the walls.
  bool container = false;
  double floor = 0.0;
  Eigen::Vector2d inner_half = Eigen::Vector2d::Zero();

  Eigen::Vector2d halfFootprint() const { return 0.5 * (box_max - box_min).head<2>(); }
  double height() const { return box_max.z() - box_min.z(); }
};

std::map<std::string, ClassShape> classShapes(const ObjectCatalog& catalog);

struct GeneratorOptions {
  std::string catalog = "package://scene_graph_tracker/config/objects.yaml";
  std::string mesh_dir;    // written into each scenario when not empty ("" = the catalog's)
  double duration = 20.0;  // s
  int min_objects = 3;
  int max_objects = 10;
  int max_per_class = 4;
  double max_carry_speed = 1.0;     // m/s
  double max_odometry_error = 0.4;  // m, start error of map -> odom
  double max_odometry_yaw_deg = 8.0;
  double max_noise_factor = 3.0;  // depth noise, times the demo's
  double max_miss_probability = 0.2;
  double max_false_positives = 0.3;  // per frame
};

struct GeneratedKey {
  double t = 0.0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  // workbench frame
  double yaw_deg = 0.0;
};

struct GeneratedObject {
  std::string id, class_name;
  std::vector<GeneratedKey> keys;
};

struct GeneratedDistractor {
  std::string id;
  std::string shape;                                      // box or cylinder
  Eigen::Vector3d size = Eigen::Vector3d::Constant(0.1);  // box
  double radius = 0.0, height = 0.0;                      // cylinder
  Eigen::Vector3d color = Eigen::Vector3d::Constant(0.5);
  std::vector<GeneratedKey> keys;
};

struct GeneratedScenario {
  std::string name;
  std::uint32_t seed = 0;
  double duration = 0.0;
  std::vector<std::string> kinds;  // what the scenario holds: stack_same, container, carry, ...
  std::vector<GeneratedObject> objects;
  std::vector<GeneratedDistractor> distractors;
  std::vector<RelationSpec> relations;  // object "workbench" is the bench top
  std::vector<GeneratedKey> robot;      // xyz.z unused
  double noise_factor = 1.0;
  Eigen::Vector3d odometry_error = Eigen::Vector3d::Zero();  // dx, dy (m), dyaw (rad)
  double miss_probability = 0.0, false_positives = 0.0;
  double hidden_fraction = 0.0;  // the largest share of objects one occluder is placed to hide
};

// One scenario from `seed`, named `name`. Deterministic: the same inputs give the same scenario.
GeneratedScenario generateScenario(const GeneratorOptions& options,
                                   const std::map<std::string, ClassShape>& shapes,
                                   std::uint32_t seed, const std::string& name);

// The scenario as a file loadScenario() reads (format: README.md, "Scenario format").
void writeScenarioYaml(const GeneratedScenario& scenario, const GeneratorOptions& options,
                       std::ostream& out);

}  // namespace sgt::sim
