#include "scene_graph_tracker/simulation/scenario_world.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::sim {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Kinds of random draws; each frame's draws come from their own generator.
enum Stream : std::uint64_t { kDepthNoise = 1, kLidarNoise = 2, kDetections = 3, kOdometry = 4 };

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint32_t seedFor(std::uint32_t seed, Stream stream, std::uint64_t index) {
  return static_cast<std::uint32_t>(
      splitmix64(splitmix64((static_cast<std::uint64_t>(seed) << 8) ^ stream) + index));
}

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

std::shared_ptr<const TriangleMesh> distractorMesh(const DistractorSpec& d) {
  switch (d.shape) {
    case Shape::Box:
      return std::make_shared<TriangleMesh>(makeBox(d.size, 2));
    case Shape::Cylinder:
      return std::make_shared<TriangleMesh>(makeCylinder(d.radius, d.height, 48));
    case Shape::Sphere:
      return std::make_shared<TriangleMesh>(makeSphere(d.radius, 48, 24));
  }
  return nullptr;
}

}  // namespace

ScenarioWorld::ScenarioWorld(const Scenario& scenario) : s_(scenario) {
  scene_ = std::make_unique<RaycastScene>();
  scene_->setStaticMap(s_.static_map, kStaticMapNode);
  colours_.static_map = kStaticMapNode;
  style_.wall_height = s_.world.kind == WorldSpec::Kind::Building
                           ? s_.world.building.wall_height
                           : s_.static_map->boundingBox().max().z();
  std::map<std::string, MeshId> class_mesh;
  for (std::size_t i = 0; i < s_.objects.size(); ++i) {
    const ObjectSpec& o = s_.objects[i];
    auto it = class_mesh.find(o.class_name);
    if (it == class_mesh.end())
      it = class_mesh.emplace(o.class_name, scene_->addMesh(s_.catalog->get(o.class_name).mesh))
               .first;
    scene_->addInstance(objectNode(i), it->second, o.trajectory.at(0.0));
    colours_.albedo[objectNode(i)] = o.color ? *o.color : classColour(o.class_name);
  }
  for (std::size_t i = 0; i < s_.distractors.size(); ++i) {
    const DistractorSpec& d = s_.distractors[i];
    scene_->addInstance(distractorNode(i), scene_->addMesh(distractorMesh(d)),
                        d.trajectory.at(0.0));
    colours_.albedo[distractorNode(i)] = d.color;
  }
  scene_->commit();
  camera_rays_ = std::make_shared<const SensorRays>(makeRays(s_.camera.model));
  lidar_rays_ = std::make_shared<const SensorRays>(makeRays(s_.lidar.model));
  const Eigen::Vector3d& e = s_.noise.odom_initial_error;
  T_map_odom_ = basePose(0.0) * planar(e.x(), e.y(), e.z()) * basePose(0.0).inverse();
  simulateOdometry();
}

ScenarioWorld::~ScenarioWorld() = default;

Label ScenarioWorld::labelOf(NodeId node) const {
  if (node == kStaticMapNode) return kLabelStaticMap;
  if (node >= kFirstObjectNode && node < objectNode(s_.objects.size())) return kLabelObject;
  if (node >= kFirstDistractorNode && node < distractorNode(s_.distractors.size()))
    return kLabelDistractor;
  return kLabelNoReturn;
}

// ---------------------------------------------------------------------------- odometry
void ScenarioWorld::simulateOdometry() {
  const auto steps = static_cast<std::size_t>(std::ceil(s_.duration / kOdomStep)) + 1;
  std::mt19937 rng(seedFor(s_.seed, kOdometry, 0));
  std::normal_distribution<double> gauss(0.0, 1.0);
  double x = 0.0, y = 0.0, yaw = 0.0;
  odom_x_.assign(1, 0.0), odom_y_.assign(1, 0.0), odom_yaw_.assign(1, 0.0);
  Eigen::Isometry3d prev = basePose(0.0);
  for (std::size_t k = 1; k <= steps; ++k) {
    const Eigen::Isometry3d cur = basePose(static_cast<double>(k) * kOdomStep);
    const Eigen::Isometry3d d = prev.inverse() * cur;
    prev = cur;
    const double dist = std::hypot(d.translation().x(), d.translation().y());
    const double dyaw = std::atan2(d.linear()(1, 0), d.linear()(0, 0));
    const double st = s_.noise.odom_translation_sigma * std::sqrt(dist);
    const double sr = s_.noise.odom_rotation_sigma * std::sqrt(dist + std::abs(dyaw));
    const double dx = d.translation().x() + st * gauss(rng),
                 dy = d.translation().y() + st * gauss(rng);
    x += std::cos(yaw) * dx - std::sin(yaw) * dy;
    y += std::sin(yaw) * dx + std::cos(yaw) * dy;
    yaw += dyaw + sr * gauss(rng);
    odom_x_.push_back(x), odom_y_.push_back(y), odom_yaw_.push_back(yaw);
  }
}

Eigen::Isometry3d ScenarioWorld::odometry(double t) const {
  const double u = std::clamp(t / kOdomStep, 0.0, static_cast<double>(odom_x_.size() - 1));
  const auto k = std::min(static_cast<std::size_t>(u), odom_x_.size() - 2);
  const double s = u - static_cast<double>(k);
  auto lerp = [&](const std::vector<double>& v) { return v[k] + s * (v[k + 1] - v[k]); };
  return basePose(0.0) * planar(lerp(odom_x_), lerp(odom_y_), lerp(odom_yaw_));
}

// ---------------------------------------------------------------------------- sensors
void ScenarioWorld::setTime(double t) {
  for (std::size_t i = 0; i < s_.objects.size(); ++i)
    scene_->setInstancePose(objectNode(i), s_.objects[i].trajectory.at(t));
  for (std::size_t i = 0; i < s_.distractors.size(); ++i)
    scene_->setInstancePose(distractorNode(i), s_.distractors[i].trajectory.at(t));
  scene_->commit();
}

CameraFrame ScenarioWorld::renderCamera(double t, std::uint64_t frame_index) {
  setTime(t);
  CameraFrame f;
  f.t = t;
  f.T_map_base = basePose(t);
  f.T_map_camera = f.T_map_base * s_.camera.T_base_camera;
  const SensorRays& rays = *camera_rays_;
  const SimulatedScan scan = simulate(*scene_, rays, f.T_map_camera);
  f.rgb = renderRgb(scan, f.T_map_camera, colours_, style_);

  // True depth of in-range hits, then the dropouts: grazing incidence and depth edges.
  const int W = scan.width, H = scan.height;
  const std::size_t n = scan.range.size();
  std::vector<float> z(n, kNaN);
  for (std::size_t i = 0; i < n; ++i)
    if (scan.node[i] != kNoNode && scan.range[i] >= rays.range_min &&
        scan.range[i] <= rays.range_max)
      z[i] = scan.points[i].z();
  const NoiseSpec& noise = s_.noise;
  const float cos_limit =
      noise.depth_max_incidence_deg >= 90.0
          ? -1.0f
          : static_cast<float>(std::cos(noise.depth_max_incidence_deg * M_PI / 180.0));
  const auto jump = static_cast<float>(noise.depth_edge_jump);
  std::vector<float> ranges(n, kNaN);
  tbb::parallel_for(0, H, [&](int v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      if (!std::isfinite(z[i])) continue;
      if (std::abs(rays.directions[i].dot(scan.normals[i])) < cos_limit) continue;
      if (jump > 0.0f) {
        auto edge = [&](int du, int dv) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || vv < 0 || uu >= W || vv >= H) return false;
          const float zj = z[static_cast<std::size_t>(vv) * W + uu];
          return !std::isfinite(zj) || std::abs(zj - z[i]) > jump;
        };
        if (edge(-1, 0) || edge(1, 0) || edge(0, -1) || edge(0, 1)) continue;
      }
      ranges[i] = scan.range[i];
    }
  });
  RangeMeasurements m =
      fromRanges(s_.camera.model, camera_rays_, std::move(ranges), f.T_map_camera, "camera");
  if (noise.depth_sigma_at_1m > 0.0)
    addDepthNoise(m, noise.depth_sigma_at_1m, seedFor(s_.seed, kDepthNoise, frame_index));

  f.depth.assign(n, kNaN);
  f.labels.assign(n, kLabelNoReturn);
  f.seen = scan.node;
  f.visible_pixels.assign(s_.objects.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(m.range[i])) continue;
    f.depth[i] = m.range[i] * rays.directions[i].z();
    f.labels[i] = labelOf(scan.node[i]);
    if (f.labels[i] == kLabelObject)
      ++f.visible_pixels[static_cast<std::size_t>(scan.node[i] - kFirstObjectNode)];
  }
  f.T_map_objects.reserve(s_.objects.size());
  for (const auto& o : s_.objects) f.T_map_objects.push_back(o.trajectory.at(t));
  return f;
}

LidarFrame ScenarioWorld::scanLidar(double t, std::uint64_t frame_index) {
  setTime(t);
  LidarFrame f;
  f.t = t;
  f.T_map_base = basePose(t);
  f.T_map_lidar = f.T_map_base * s_.lidar.T_base_lidar;
  const SensorRays& rays = *lidar_rays_;
  const SimulatedScan scan = simulate(*scene_, rays, f.T_map_lidar);
  const std::size_t n = scan.range.size();
  std::vector<float> ranges(n, kNaN);
  for (std::size_t i = 0; i < n; ++i)
    if (scan.node[i] != kNoNode && scan.range[i] >= rays.range_min &&
        scan.range[i] <= rays.range_max)
      ranges[i] = scan.range[i];
  RangeMeasurements m =
      fromRanges(s_.lidar.model, lidar_rays_, std::move(ranges), f.T_map_lidar, "velodyne");
  if (s_.noise.lidar_range_sigma > 0.0)
    addRangeNoise(m, s_.noise.lidar_range_sigma, seedFor(s_.seed, kLidarNoise, frame_index));
  f.range = std::move(m.range);
  f.intensity.assign(n, 0.0f);
  f.labels.assign(n, kLabelNoReturn);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(f.range[i])) continue;
    f.intensity[i] = 100.0f * std::abs(rays.directions[i].dot(scan.normals[i]));
    f.labels[i] = labelOf(scan.node[i]);
  }
  return f;
}

// ---------------------------------------------------------------------------- detections
std::vector<Hypothesis> ScenarioWorld::detect(const CameraFrame& frame,
                                              std::uint64_t frame_index) const {
  std::vector<Hypothesis> out;
  const DetectionSpec& d = s_.detections;
  if (!d.enabled) return out;
  std::mt19937 rng(seedFor(s_.seed, kDetections, frame_index));
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Isometry3d T_camera_map = frame.T_map_camera.inverse();
  const double sigma_r = d.sigma_r_deg * M_PI / 180.0;
  for (std::size_t i = 0; i < s_.objects.size(); ++i) {
    if (frame.visible_pixels[i] < d.min_visible_pixels) continue;
    if (uniform(rng) < d.miss_probability) continue;
    Hypothesis h;
    h.class_name = s_.objects[i].class_name;
    h.object = static_cast<int>(i);
    h.T_camera_object =
        disturbPose(T_camera_map * frame.T_map_objects[i], d.sigma_t, sigma_r, rng, gauss);
    const double seen = std::min(1.0, frame.visible_pixels[i] / 2000.0);
    h.score = static_cast<float>(std::clamp(0.55 + 0.4 * seen + 0.03 * gauss(rng), 0.05, 1.0));
    out.push_back(std::move(h));
  }
  // False positives: a random class standing upright (random yaw) on a random visible surface.
  if (d.false_positives_per_frame > 0.0 && s_.catalog->size() > 0) {
    std::poisson_distribution<int> count(d.false_positives_per_frame);
    const int k = count(rng);
    const std::vector<std::string> names = s_.catalog->names();
    const SensorRays& rays = *camera_rays_;
    for (int j = 0; j < k; ++j) {
      const std::string& cls =
          names[std::uniform_int_distribution<std::size_t>(0, names.size() - 1)(rng)];
      std::size_t pixel = frame.depth.size();
      for (int tries = 0; tries < 100 && pixel == frame.depth.size(); ++tries) {
        const std::size_t p =
            std::uniform_int_distribution<std::size_t>(0, frame.depth.size() - 1)(rng);
        if (std::isfinite(frame.depth[p])) pixel = p;
      }
      if (pixel == frame.depth.size()) break;
      const Eigen::Vector3d p_cam =
          (rays.directions[pixel] * (frame.depth[pixel] / rays.directions[pixel].z()))
              .cast<double>();
      Eigen::Isometry3d T_map = Eigen::Isometry3d::Identity();
      T_map.linear() =
          Eigen::AngleAxisd(2.0 * M_PI * uniform(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T_map.translation() = frame.T_map_camera * p_cam -
                            Eigen::Vector3d::UnitZ() * s_.catalog->get(cls).box.min().z();
      Hypothesis h;
      h.class_name = cls;
      h.T_camera_object = T_camera_map * T_map;
      h.score = static_cast<float>(0.2 + 0.4 * uniform(rng));
      out.push_back(std::move(h));
    }
  }
  return out;
}

}  // namespace sgt::sim
