// Occluder geometry for the generated scenarios, and the finished scenario with its sensors.
#include <algorithm>
#include <cmath>

#include "scenario_generator_plan.hpp"

namespace sgt::sim::gen {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kPersonHeight = 1.75;

// The occluder's keyframe at time t where `at` puts it, moved `away` metres across the line of
// sight (off stage), at height z, turned to face the camera.
GeneratedKey occluderKey(double t, const Cover& at, double away, double z) {
  GeneratedKey k;
  k.t = t;
  k.xyz = at.centre;
  k.xyz.head<2>() += away * at.across;
  k.xyz.z() = z;
  k.yaw_deg = std::atan2(at.across.y(), at.across.x()) / kDeg;
  return k;
}

}  // namespace

// Where an occluder must stand at time t, at share f of the way from the targets to the camera,
// to cover them all as the camera sees them.
Cover Plan::cover(const std::vector<const PlannedObject*>& targets, double t, double f) const {
  const Eigen::Vector3d eye = eyeAt(t);
  std::vector<Eigen::Vector3d> p;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const PlannedObject* o : targets)
    c += p.emplace_back(poseAt(o->keys, t).xyz) / targets.size();
  const Eigen::Vector2d sight = (eye - c).head<2>().normalized();
  Cover out;
  out.across = {-sight.y(), sight.x()};
  double lo = 1e9, hi = -1e9, zb = 1e9, zt = -1e9;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const ClassShape& s = shape(*targets[i]);
    const double s_i = (p[i] - c).head<2>().dot(out.across), r = s.halfFootprint().norm();
    lo = std::min(lo, s_i - r), hi = std::max(hi, s_i + r);
    zb = std::min(zb, p[i].z() + s.box_min.z()), zt = std::max(zt, p[i].z() + s.box_max.z());
  }
  out.width = (1 - f) * (hi - lo) + 0.06;
  out.z_low = zb + f * (eye.z() - zb) - 0.03;
  out.z_high = zt + f * (eye.z() - zt) + 0.03;
  out.centre = c + f * (eye - c);
  out.centre.head<2>() += (1 - f) * 0.5 * (hi + lo) * out.across;
  return out;
}

// A person stands on the floor in front of the bench, so farther from the objects than a board:
// the share of the way to the camera that puts them there (outside (0, 0.8): no room for one).
double Plan::personShare(const std::vector<const PlannedObject*>& targets, double t) const {
  const Eigen::Vector3d eye = eyeAt(t);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const PlannedObject* o : targets) c += poseAt(o->keys, t).xyz / targets.size();
  return (kBenchHalfY + 0.35 - c.y()) / std::max(1e-3, eye.y() - c.y());
}

GeneratedDistractor Plan::occluder(int index, const std::vector<const PlannedObject*>& targets,
                                   double t0, double duration) {
  GeneratedDistractor d;
  d.id = "occluder_" + std::to_string(index + 1);
  const double kind = uniform(rng_, 0.0, 1.0);
  double f = uniform(rng_, 0.3, 0.6);
  const double person_f = personShare(targets, t0);
  const bool person =
      kind < 0.3 && person_f > 0.0 && person_f < 0.8 && cover(targets, t0, person_f).width < 0.7;
  if (person) f = person_f;
  const Cover a = cover(targets, t0, f), b = cover(targets, t0 + duration, f);
  const double width = std::max(a.width, b.width);
  const double z_low = std::min(a.z_low, b.z_low), z_high = std::max(a.z_high, b.z_high);
  if (person) {
    d.shape = "cylinder";
    d.radius = std::max(0.2, 0.5 * width);
    d.height = kPersonHeight;
    d.color = {uniform(rng_, 0.2, 0.5), uniform(rng_, 0.2, 0.4), uniform(rng_, 0.3, 0.6)};
  } else {
    const bool board = kind < 0.7;
    d.shape = "box";
    d.size = {width, board ? 0.02 : uniform(rng_, 0.15, 0.3), z_high - z_low};
    d.color = board ? Eigen::Vector3d(0.85, 0.85, 0.8) : Eigen::Vector3d(0.7, 0.55, 0.35);
  }
  const double z = person ? kFloorZ + 0.5 * kPersonHeight : 0.5 * (z_low + z_high);
  d.keys = {occluderKey(t0 - 0.4, a, 3.0, z), occluderKey(t0, a, 0.0, z),
            occluderKey(t0 + duration, b, 0.0, z), occluderKey(t0 + duration + 0.4, b, 3.0, z)};
  for (std::size_t i = 1; i < d.keys.size(); ++i)  // no turn of more than half a turn
    d.keys[i].yaw_deg =
        d.keys[i - 1].yaw_deg + std::remainder(d.keys[i].yaw_deg - d.keys[i - 1].yaw_deg, 360.0);
  return d;
}

GeneratedScenario Plan::finish(const std::string& name, std::uint32_t seed) {
  GeneratedScenario g;
  g.name = name;
  g.seed = seed;
  g.duration = options_.duration;
  g.kinds.assign(kinds_.begin(), kinds_.end());
  for (const PlannedObject& o : objects_) {
    g.objects.push_back({o.id, o.class_name, o.keys});
    for (const SupportSpan& s : o.supports)
      if (s.to > s.from) g.relations.push_back({o.id, s.relation, s.object, s.from, s.to});
  }
  g.distractors = distractors_;
  g.robot = robot_;
  g.noise_factor = uniform(rng_, 1.0, options_.max_noise_factor);
  const double r = uniform(rng_, 0.0, options_.max_odometry_error),
               heading = uniform(rng_, -M_PI, M_PI);
  g.odometry_error = {
      r * std::cos(heading), r * std::sin(heading),
      uniform(rng_, -options_.max_odometry_yaw_deg, options_.max_odometry_yaw_deg) * kDeg};
  g.miss_probability = uniform(rng_, 0.0, options_.max_miss_probability);
  g.false_positives = uniform(rng_, 0.0, options_.max_false_positives);
  g.hidden_fraction = hidden_fraction_;
  return g;
}

}  // namespace sgt::sim::gen
