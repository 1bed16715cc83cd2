// Manipulations of the generated scenarios: a person puts objects into containers and takes them
// out, carries them across the bench or out of the camera's view and back, and stacks them. One
// manipulation at a time; each object is handled at most once (twice for into and out of a
// container).
#include <algorithm>
#include <cmath>
#include <functional>

#include "scenario_generator_plan.hpp"

namespace sgt::sim::gen {

using relations::Relation;

namespace {

double wrapDeg(double a) { return std::remainder(a, 360.0); }

}  // namespace

void Plan::manipulate() {
  using Event = std::function<std::optional<double>(double)>;
  std::vector<std::pair<double, Event>> events = {
      {0.6, [this](double t) { return putIntoContainer(t); }},
      {0.5, [this](double t) { return carry(t, false); }},
      {0.4, [this](double t) { return carry(t, true); }},
      {0.3, [this](double t) { return putOntoStack(t); }},
      {0.3, [this](double t) { return carry(t, false); }},
  };
  std::shuffle(events.begin(), events.end(), rng_);
  double t = uniform(rng_, 1.5, 4.0);
  for (const auto& [probability, event] : events) {
    if (t > options_.duration - 4.0) break;
    if (!chance(rng_, probability)) continue;
    if (const auto end = event(t)) t = *end + uniform(rng_, 0.5, 2.0);
  }
}

std::vector<PlannedObject*> Plan::movable(bool containers_too) {
  std::vector<PlannedObject*> out;
  for (PlannedObject& o : objects_)
    if (!o.busy && !o.fixed && !o.holds && (containers_too || !shape(o).container))
      out.push_back(&o);
  return out;
}

PlannedObject& Plan::pick(const std::vector<PlannedObject*>& candidates) {
  return *candidates[uniformInt(rng_, 0, static_cast<int>(candidates.size()) - 1)];
}

std::optional<double> Plan::putIntoContainer(double t) {
  std::vector<std::pair<PlannedObject*, PlannedObject*>> pairs;  // (container, content)
  for (PlannedObject& c : objects_) {
    if (!shape(c).container || c.holds || c.busy) continue;
    for (PlannedObject* o : movable(false)) {
      const Eigen::Vector2d h = shape(*o).halfFootprint(), in = shape(c).inner_half;
      if ((h.x() < in.x() && h.y() < in.y()) || (h.y() < in.x() && h.x() < in.y()))
        pairs.push_back({&c, o});
    }
  }
  if (pairs.empty()) return std::nullopt;
  auto [container, content] = pairs[uniformInt(rng_, 0, static_cast<int>(pairs.size()) - 1)];
  const ClassShape &sc = shape(*container), &so = shape(*content);
  const GeneratedKey c = poseAt(container->keys, t);
  const Eigen::Vector2d h = so.halfFootprint();
  GeneratedKey to;
  to.yaw_deg = c.yaw_deg + ((h.x() < sc.inner_half.x() && h.y() < sc.inner_half.y()) ? 0 : 90);
  const Eigen::Vector2d centre = footprint(sc, c.xyz.head<2>(), c.yaw_deg * M_PI / 180).centre;
  to.xyz.head<2>() = centre - Eigen::Rotation2Dd(to.yaw_deg * M_PI / 180) *
                                  (0.5 * (so.box_min + so.box_max).head<2>());
  to.xyz.z() = c.xyz.z() + sc.floor + restZ(so) + 0.001;
  container->holds = container->fixed = content->busy = true;
  double end = move(*content, t, to);
  openSupport(*content, Relation::In, container->id, end - kLiftTime, to);
  kinds_.insert("container_in");
  const double out = end + uniform(rng_, 2.0, 4.0);
  if (!chance(rng_, 0.5) || out > options_.duration - 3.0) return end;
  const auto spot = freeSpot(so, out);
  if (!spot) return end;
  end = move(*content, out, *spot);
  openSupport(*content, Relation::On, kWorkbenchName, end - kLiftTime, *spot);
  kinds_.insert("container_out");
  return end;
}

std::optional<double> Plan::carry(double t, bool out_of_view) {
  const std::vector<PlannedObject*> candidates = movable(true);
  if (candidates.empty()) return std::nullopt;
  PlannedObject& o = pick(candidates);
  const auto spot = freeSpot(shape(o), t);
  if (!spot) return std::nullopt;
  o.busy = true;
  std::optional<Eigen::Vector2d> via;
  double hold = 0.0;
  if (out_of_view) {
    const GeneratedKey from = poseAt(o.keys, t);
    via = Eigen::Vector2d(from.xyz.x() < 0 ? -1.6 : 1.6, from.xyz.y());
    hold = uniform(rng_, 1.0, 3.0);
  }
  const double end = move(o, t, *spot, via, hold);
  openSupport(o, Relation::On, kWorkbenchName, end - kLiftTime, *spot);
  kinds_.insert(out_of_view ? "carry_out_of_view" : "carry");
  return end;
}

std::optional<double> Plan::putOntoStack(double t) {
  std::vector<std::pair<PlannedObject*, PlannedObject*>> pairs;  // (base, top)
  for (PlannedObject* top : movable(false))
    for (PlannedObject& base : objects_)
      if (!base.busy && canCarry(base, *top) && base.supports.size() == 1 &&
          base.supports.front().object == kWorkbenchName)
        pairs.push_back({&base, top});
  if (pairs.empty()) return std::nullopt;
  auto [base, top] = pairs[uniformInt(rng_, 0, static_cast<int>(pairs.size()) - 1)];
  base->fixed = base->holds = top->busy = true;
  const GeneratedKey to = restingOn(*base, *top, t);
  const double end = move(*top, t, to);
  openSupport(*top, Relation::On, base->id, end - kLiftTime, to);
  kinds_.insert(base->class_name == top->class_name ? "stack_same" : "stack_mixed");
  kinds_.insert("stack_put");
  return end;
}

double Plan::move(PlannedObject& o, double t0, const GeneratedKey& to,
                  const std::optional<Eigen::Vector2d>& via, double hold) {
  const double speed = uniform(rng_, 0.3, options_.max_carry_speed);
  GeneratedKey k = poseAt(o.keys, t0);
  k.t = t0;
  if (o.keys.back().t < t0) o.keys.push_back(k);
  const double rise = lift_z_ - k.xyz.z();
  closeSupport(o, t0, rise);
  const auto travel = [&](const Eigen::Vector2d& xy, double yaw_deg) {
    const double distance = (xy - k.xyz.head<2>()).norm();
    k.t += std::max(0.3, distance / speed);
    k.xyz.head<2>() = xy;
    k.yaw_deg += wrapDeg(yaw_deg - k.yaw_deg);
    o.keys.push_back(k);
  };
  k.t += kLiftTime;
  k.xyz.z() = lift_z_;
  o.keys.push_back(k);
  if (via) {
    travel(*via, k.yaw_deg);
    k.t += hold;
    if (hold > 0) o.keys.push_back(k);
  }
  travel(to.xyz.head<2>(), to.yaw_deg);
  k.t += kLiftTime;
  k.xyz.z() = to.xyz.z();
  o.keys.push_back(k);
  return k.t;
}

// The support ends when the object has risen 2 cm (the relation engine's on_max_distance) or,
// from a container, when its bottom clears the container's top.
void Plan::closeSupport(PlannedObject& o, double t0, double rise) {
  SupportSpan& s = o.supports.back();
  double needed = 0.02;
  if (s.relation == Relation::In) {
    const auto c = std::find_if(objects_.begin(), objects_.end(),
                                [&](const PlannedObject& p) { return p.id == s.object; });
    const double top = poseAt(c->keys, t0).xyz.z() + shape(*c).box_max.z();
    needed = top - bottomZ(o, poseAt(o.keys, t0).xyz.z());
  }
  s.to = t0 + kLiftTime * std::clamp(needed / rise, 0.0, 1.0);
}

void Plan::openSupport(PlannedObject& o, Relation relation, const std::string& object,
                       double t_lower, const GeneratedKey& to) {
  const double drop = lift_z_ - to.xyz.z();
  double remaining = 0.02;  // lowered to within 2 cm of its support
  if (relation == Relation::In) {
    const auto c = std::find_if(objects_.begin(), objects_.end(),
                                [&](const PlannedObject& p) { return p.id == object; });
    const double top = poseAt(c->keys, t_lower).xyz.z() + shape(*c).box_max.z();
    remaining = top - bottomZ(o, to.xyz.z());
  }
  o.supports.push_back(
      {relation, object, t_lower + kLiftTime * std::clamp(1.0 - remaining / drop, 0.0, 1.0)});
}

}  // namespace sgt::sim::gen
