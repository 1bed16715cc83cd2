// The scenario generator: objects and their layout, stacks, manipulations (scenario_generator.hpp).
// The robot's path and the occluders: scenario_generator_scene.cpp.
#include "scene_graph_tracker/simulation/scenario_generator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scenario_generator_plan.hpp"

namespace sgt::sim::gen {

using relations::Relation;

Plan::Plan(const GeneratorOptions& options, const std::map<std::string, ClassShape>& shapes,
           std::uint32_t seed)
    : options_(options), shapes_(shapes), rng_(seed) {
  if (shapes_.empty()) throw std::invalid_argument("generateScenario: the catalog has no classes");
  lift_z_ = 0.15;
  for (const auto& [name, s] : shapes_) lift_z_ = std::max(lift_z_, 2.0 * s.height() + 0.1);
}

const ClassShape& Plan::shape(const PlannedObject& o) const { return shapes_.at(o.class_name); }

double Plan::restZ(const ClassShape& s) const { return -s.box_min.z() + 0.001; }

Footprint Plan::footprint(const ClassShape& s, const Eigen::Vector2d& origin, double yaw) const {
  Footprint f;
  f.half = s.halfFootprint();
  f.yaw = yaw;
  f.centre = origin + Eigen::Rotation2Dd(yaw) * (0.5 * (s.box_min + s.box_max).head<2>());
  return f;
}

bool Plan::free(const Footprint& f, double margin) const {
  if (!insideUsableArea(f)) return false;
  return std::none_of(reserved_.begin(), reserved_.end(),
                      [&](const Footprint& r) { return overlaps(f, r, margin); });
}

std::optional<GeneratedKey> Plan::freeSpot(const ClassShape& s, double t) {
  for (int attempt = 0; attempt < 300; ++attempt) {
    GeneratedKey k;
    k.t = t;
    k.yaw_deg = uniform(rng_, -180.0, 180.0);
    k.xyz = {uniform(rng_, -kUsableHalfX, kUsableHalfX), uniform(rng_, -kUsableHalfY, kUsableHalfY),
             restZ(s)};
    const Footprint f = footprint(s, k.xyz.head<2>(), k.yaw_deg * M_PI / 180.0);
    if (free(f, 0.03)) {
      reserved_.push_back(f);
      return k;
    }
  }
  return std::nullopt;
}

void Plan::chooseClasses() {
  std::vector<std::string> names;
  for (const auto& [name, s] : shapes_) names.push_back(name);
  const int n = uniformInt(rng_, options_.min_objects, options_.max_objects);
  std::map<std::string, int> count;
  const auto add = [&](const std::string& c) {
    objects_.push_back({c + "_" + std::to_string(++count[c]), c, {}, {}});
  };
  // Identical parts: a group of 3-4 of one class that is not a container, half of the time.
  std::vector<std::string> solids;
  for (const auto& [name, s] : shapes_)
    if (!s.container) solids.push_back(name);
  if (!solids.empty() && chance(rng_, 0.5)) {
    twins_class_ = solids[uniformInt(rng_, 0, static_cast<int>(solids.size()) - 1)];
    const int k = std::min(uniformInt(rng_, 3, std::min(4, options_.max_per_class)), n);
    for (int i = 0; i < k; ++i) add(twins_class_);
  }
  for (int guard = 0; static_cast<int>(objects_.size()) < n && guard < 1000; ++guard) {
    const std::string& c = names[uniformInt(rng_, 0, static_cast<int>(names.size()) - 1)];
    const int cap =
        shapes_.at(c).container ? std::min(2, options_.max_per_class) : options_.max_per_class;
    if (count[c] < cap) add(c);
  }
}

bool Plan::placeSideBySide(std::vector<PlannedObject*>& group) {
  if (group.size() < 2 || !chance(rng_, 0.5)) return false;
  const ClassShape& s = shape(*group.front());
  for (int attempt = 0; attempt < 100; ++attempt) {
    const double yaw = uniform(rng_, -M_PI, M_PI), gap = uniform(rng_, 0.01, 0.03);
    const Eigen::Vector2d step =
        Eigen::Rotation2Dd(yaw) * Eigen::Vector2d(0, 2 * s.halfFootprint().y() + gap);
    const Eigen::Vector2d start(uniform(rng_, -kUsableHalfX, kUsableHalfX),
                                uniform(rng_, -kUsableHalfY, kUsableHalfY));
    std::vector<Footprint> row;
    for (std::size_t i = 0; i < group.size(); ++i)
      row.push_back(footprint(s, start + static_cast<double>(i) * step, yaw));
    if (!std::all_of(row.begin(), row.end(), [&](const Footprint& f) { return free(f, 0.03); }))
      continue;
    for (std::size_t i = 0; i < group.size(); ++i) {
      reserved_.push_back(row[i]);
      const Eigen::Vector2d xy = start + static_cast<double>(i) * step;
      group[i]->keys = {{0.0, {xy.x(), xy.y(), restZ(s)}, yaw * 180.0 / M_PI}};
      group[i]->supports = {{Relation::On, kWorkbenchName}};
    }
    kinds_.insert("identical_side_by_side");
    return true;
  }
  return false;
}

void Plan::stackStatic() {
  if (!chance(rng_, 0.4)) return;
  // The top of the stack is an object not yet placed; the base one already on the bench.
  for (PlannedObject& top : objects_) {
    if (!top.keys.empty() || shape(top).container) continue;
    std::vector<PlannedObject*> bases;
    for (PlannedObject& b : objects_)
      if (!b.keys.empty() && canCarry(b, top) && b.supports.front().object == kWorkbenchName)
        bases.push_back(&b);
    if (bases.empty()) continue;
    // Prefer a base of the same class half of the time (identical parts stacked).
    std::stable_partition(bases.begin(), bases.end(),
                          [&](const PlannedObject* b) { return b->class_name == top.class_name; });
    const bool same = bases.front()->class_name == top.class_name && chance(rng_, 0.5);
    PlannedObject& base = same ? *bases.front() : *bases[uniformInt(rng_, 0, bases.size() - 1)];
    const GeneratedKey k = restingOn(base, top, 0.0);
    top.keys = {k};
    top.supports = {{Relation::On, base.id}};
    top.fixed = base.fixed = base.holds = true;
    kinds_.insert(base.class_name == top.class_name ? "stack_same" : "stack_mixed");
    return;
  }
}

bool Plan::canCarry(const PlannedObject& base, const PlannedObject& top) const {
  const ClassShape &b = shape(base), &t = shape(top);
  if (b.container || base.holds || &base == &top) return false;
  const Eigen::Vector2d hb = b.halfFootprint(), ht = t.halfFootprint();
  return hb.x() * hb.y() >= 0.5 * ht.x() * ht.y();
}

GeneratedKey Plan::restingOn(const PlannedObject& base, const PlannedObject& top, double t) {
  const GeneratedKey b = poseAt(base.keys, t);
  const ClassShape &sb = shape(base), &st = shape(top);
  GeneratedKey k;
  k.t = t;
  k.yaw_deg = b.yaw_deg + uniform(rng_, -10.0, 10.0);
  const Eigen::Vector2d base_centre = footprint(sb, b.xyz.head<2>(), b.yaw_deg * M_PI / 180).centre;
  const Eigen::Vector2d offset =
      Eigen::Rotation2Dd(k.yaw_deg * M_PI / 180) * (0.5 * (st.box_min + st.box_max).head<2>());
  k.xyz.head<2>() = base_centre - offset;
  k.xyz.z() = b.xyz.z() + sb.box_max.z() + restZ(st);
  return k;
}

void Plan::layOut() {
  // Containers first (the largest), then identical parts, then the rest at random.
  std::stable_sort(objects_.begin(), objects_.end(),
                   [&](const PlannedObject& a, const PlannedObject& b) {
                     return shape(a).container > shape(b).container;
                   });
  std::vector<PlannedObject*> twins;
  for (PlannedObject& o : objects_)
    if (o.class_name == twins_class_) twins.push_back(&o);
  for (PlannedObject& o : objects_) {
    if (o.class_name == twins_class_ || !shape(o).container) continue;
    placeOnBench(o);
  }
  if (!placeSideBySide(twins))
    for (PlannedObject* o : twins) placeOnBench(*o);
  stackStatic();
  for (PlannedObject& o : objects_)
    if (o.keys.empty()) placeOnBench(o);
  // Objects that found no room are left out.
  objects_.erase(std::remove_if(objects_.begin(), objects_.end(),
                                [](const PlannedObject& o) { return o.keys.empty(); }),
                 objects_.end());
}

void Plan::placeOnBench(PlannedObject& o) {
  if (!o.keys.empty()) return;
  if (const auto k = freeSpot(shape(o), 0.0)) {
    o.keys = {*k};
    o.supports = {{Relation::On, kWorkbenchName}};
  }
}

}  // namespace sgt::sim::gen

namespace sgt::sim {

GeneratedScenario generateScenario(const GeneratorOptions& options,
                                   const std::map<std::string, ClassShape>& shapes,
                                   std::uint32_t seed, const std::string& name) {
  gen::Plan plan(options, shapes, seed);
  plan.chooseClasses();
  plan.layOut();
  plan.pathRobot();
  plan.manipulate();
  plan.addClutter();
  plan.occlude();
  return plan.finish(name, seed);
}

}  // namespace sgt::sim
