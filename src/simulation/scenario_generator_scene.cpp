// The generated scenarios' robot path, unknown clutter and occluders, sensor noise, and the result.
#include <algorithm>
#include <cmath>

#include "scenario_generator_plan.hpp"

namespace sgt::sim::gen {

namespace {

constexpr double kDeg = M_PI / 180.0;

double yawTowardBench(double x, double y) { return std::atan2(-y, -x) / kDeg; }

GeneratedKey robotKey(double t, double x, double y, double yaw_deg) {
  return {t, {x, y, 0.0}, yaw_deg};
}

}  // namespace

// Drives up to the bench from 2.2-3 m, then maybe moves sideways and back, or turns away and
// back. It ends where it arrived: the camera's mount looks at the bench from there.
void Plan::pathRobot() {
  const double x0 = uniform(rng_, -0.8, 0.8), y0 = uniform(rng_, 2.2, 3.0);
  const double x1 = uniform(rng_, -0.2, 0.2), y1 = uniform(rng_, 1.0, 1.3);
  const double wait = uniform(rng_, 0.5, 2.0), speed = uniform(rng_, 0.25, 0.45);
  const double arrive = wait + std::hypot(x1 - x0, y1 - y0) / speed;
  const GeneratedKey start = robotKey(0.0, x0, y0, yawTowardBench(x0, y0) + uniform(rng_, -5, 5));
  const GeneratedKey end = robotKey(arrive, x1, y1, yawTowardBench(x1, y1));
  robot_ = {start, start, end};
  robot_[1].t = wait;
  kinds_.insert("approach");
  double t = arrive + uniform(rng_, 0.5, 2.0);
  const auto at = [&](double dt, double x, double y, double yaw) {
    t += dt;
    robot_.push_back(robotKey(t, x, y, yaw));
  };
  std::vector<int> moves = {0, 1};
  std::shuffle(moves.begin(), moves.end(), rng_);
  for (const int move : moves) {
    if (!chance(rng_, 0.4)) continue;
    const double side = chance(rng_, 0.5) ? 1.0 : -1.0, hold = uniform(rng_, 0.5, 2.5);
    if (move == 0) {  // sideways along the bench, still facing it
      const double dx = side * uniform(rng_, 0.3, 0.5), duration = std::abs(dx) / 0.2;
      if (t + 2 * duration + hold > options_.duration - 1.0) continue;
      at(0.0, x1, y1, end.yaw_deg);
      at(duration, x1 + dx, y1, yawTowardBench(x1 + dx, y1));
      at(hold, x1 + dx, y1, yawTowardBench(x1 + dx, y1));
      at(duration, x1, y1, end.yaw_deg);
      kinds_.insert("sideways");
    } else {  // turns away from the bench and back
      const double turn = side * uniform(rng_, 70.0, 110.0);
      if (t + 3.0 + hold > options_.duration - 1.0) continue;
      at(0.0, x1, y1, end.yaw_deg);
      at(1.5, x1, y1, end.yaw_deg + turn);
      at(hold, x1, y1, end.yaw_deg + turn);
      at(1.5, x1, y1, end.yaw_deg);
      kinds_.insert("turn_away");
    }
    t += uniform(rng_, 0.5, 1.5);
  }
  if (robot_.back().t < options_.duration)
    robot_.push_back(end), robot_.back().t = options_.duration;
}

Eigen::Vector3d Plan::eyeAt(double t) const {
  const GeneratedKey k = poseAt(robot_, t);
  const double yaw = k.yaw_deg * kDeg;
  return {k.xyz.x() + kEyeForward * std::cos(yaw), k.xyz.y() + kEyeForward * std::sin(yaw),
          kFloorZ + kEyeHeight};
}

// Unknown boxes standing on the bench for the whole run, half of the time.
void Plan::addClutter() {
  if (!chance(rng_, 0.5)) return;
  const int count = uniformInt(rng_, 1, 2);
  for (int i = 0; i < count; ++i) {
    GeneratedDistractor d;
    d.id = "clutter_" + std::to_string(i + 1);
    d.shape = "box";
    d.size = {uniform(rng_, 0.08, 0.2), uniform(rng_, 0.08, 0.2), uniform(rng_, 0.06, 0.18)};
    d.color = {uniform(rng_, 0.4, 0.8), uniform(rng_, 0.3, 0.6), uniform(rng_, 0.2, 0.4)};
    ClassShape s;
    s.box_min = -0.5 * d.size;
    s.box_max = 0.5 * d.size;
    const auto spot = freeSpot(s, 0.0);
    if (!spot) continue;
    d.keys = {*spot};
    distractors_.push_back(d);
    kinds_.insert("clutter");
  }
}

void Plan::occlude() {
  const double r = uniform(rng_, 0.0, 1.0);
  const int count = r < 0.3 ? 0 : (r < 0.8 ? 1 : 2);
  for (int i = 0; i < count; ++i)
    if (occludeOnce(i)) kinds_.insert("occlusion");
}

// An occluder between the camera and a run of neighbouring objects (as the camera sees them)
// that makes up 30-100 % of the objects in view, for 0.5-5 s.
bool Plan::occludeOnce(int index) {
  const double duration = uniform(rng_, 0.5, 5.0);
  const double t0 = uniform(rng_, 2.0, options_.duration - duration - 1.0);
  if (t0 < 2.0) return false;
  const Eigen::Vector3d eye = eyeAt(t0 + 0.5 * duration);
  std::vector<std::pair<double, const PlannedObject*>> by_azimuth;
  for (const PlannedObject& o : objects_) {
    const Eigen::Vector3d p = poseAt(o.keys, t0 + 0.5 * duration).xyz;
    if (std::abs(p.x()) < kBenchHalfX)  // not carried out of view
      by_azimuth.push_back({std::atan2(p.y() - eye.y(), p.x() - eye.x()), &o});
  }
  if (by_azimuth.empty()) return false;
  std::sort(by_azimuth.begin(), by_azimuth.end());
  const int n = static_cast<int>(by_azimuth.size());
  const int k = std::clamp(static_cast<int>(std::lround(uniform(rng_, 0.3, 1.0) * n)), 1, n);
  const int first = uniformInt(rng_, 0, n - k);
  std::vector<const PlannedObject*> targets;
  for (int i = first; i < first + k; ++i) targets.push_back(by_azimuth[i].second);
  hidden_fraction_ = std::max(hidden_fraction_, static_cast<double>(k) / n);
  distractors_.push_back(occluder(index, targets, t0, duration));
  return true;
}

}  // namespace sgt::sim::gen
