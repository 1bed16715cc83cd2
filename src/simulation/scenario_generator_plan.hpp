// Internal to the scenario generator: the plan a scenario is drawn into, step by step.
//   scenario_generator.cpp        classes, layout on the bench, stacks
//   scenario_generator_events.cpp manipulations: into and out of containers, carrying, stacking
//   scenario_generator_scene.cpp  the robot's path, clutter, occluders, sensors, the result
#pragma once

#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "scenario_generator_layout.hpp"

namespace sgt::sim::gen {

// Where an occluder must stand to cover its targets as the camera sees them.
struct Cover {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector2d across = Eigen::Vector2d::UnitX();  // horizontal, across the line of sight
  double width = 0.0, z_low = 0.0, z_high = 0.0;
};

class Plan {
 public:
  Plan(const GeneratorOptions& options, const std::map<std::string, ClassShape>& shapes,
       std::uint32_t seed);

  void chooseClasses();
  void layOut();
  void pathRobot();
  void manipulate();
  void addClutter();
  void occlude();
  GeneratedScenario finish(const std::string& name, std::uint32_t seed);

 private:
  const ClassShape& shape(const PlannedObject& o) const;
  double restZ(const ClassShape& s) const;  // origin height of an object resting on the bench
  Footprint footprint(const ClassShape& s, const Eigen::Vector2d& origin, double yaw) const;
  bool free(const Footprint& f, double margin) const;
  // A free resting pose on the bench at time t (its footprint is then reserved for the run).
  std::optional<GeneratedKey> freeSpot(const ClassShape& s, double t);
  void placeOnBench(PlannedObject& o);
  bool placeSideBySide(std::vector<PlannedObject*>& group);
  void stackStatic();
  bool canCarry(const PlannedObject& base, const PlannedObject& top) const;
  GeneratedKey restingOn(const PlannedObject& base, const PlannedObject& top, double t);

  // Manipulations: each returns the time it ends, or nothing when the scene offers no candidate.
  std::optional<double> putIntoContainer(double t);
  std::optional<double> carry(double t, bool out_of_view);
  std::optional<double> putOntoStack(double t);
  std::vector<PlannedObject*> movable(bool containers_too);
  PlannedObject& pick(const std::vector<PlannedObject*>& candidates);
  // Lifts o at t0, carries it (through `via`, held there `hold` s) and lowers it at `to`;
  // closes its current support when it lifts off. Returns the time it rests again.
  double move(PlannedObject& o, double t0, const GeneratedKey& to,
              const std::optional<Eigen::Vector2d>& via = {}, double hold = 0.0);
  void closeSupport(PlannedObject& o, double t0, double rise_time);
  // Opens "relation object" for o, which is lowered over [t_lower, t_lower + kLiftTime] to `to`.
  void openSupport(PlannedObject& o, relations::Relation relation, const std::string& object,
                   double t_lower, const GeneratedKey& to);
  double bottomZ(const PlannedObject& o, double z) const { return z + shape(o).box_min.z(); }

  Eigen::Vector3d eyeAt(double t) const;  // camera centre, workbench frame
  bool occludeOnce(int index);
  GeneratedDistractor occluder(int index, const std::vector<const PlannedObject*>& targets,
                               double t0, double duration);
  Cover cover(const std::vector<const PlannedObject*>& targets, double t, double f) const;
  double personShare(const std::vector<const PlannedObject*>& targets, double t) const;

  GeneratorOptions options_;
  const std::map<std::string, ClassShape>& shapes_;
  std::mt19937 rng_;
  std::vector<PlannedObject> objects_;
  std::vector<Footprint> reserved_;  // every resting footprint of the run
  std::set<std::string> kinds_;
  std::string twins_class_;
  double lift_z_ = 0.3;  // height objects are carried at
  std::vector<GeneratedKey> robot_;
  std::vector<GeneratedDistractor> distractors_;
  double hidden_fraction_ = 0.0;
};

constexpr double kLiftTime = 0.4;  // s to lift an object off, or to lower it

}  // namespace sgt::sim::gen
