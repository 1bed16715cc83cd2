// Simulation scenarios: a static world, catalog objects and distractors on keyframed
// trajectories, a robot base trajectory, sensor mounts, noise, rates and simulated detections,
// read from YAML (format: README.md, "Scenario format"; example: config/scenarios/workbench.yaml).
//
// loadScenario() checks the whole file and throws ScenarioError naming the file, the line and the
// field ("workbench.yaml:23: objects[2].keyframes[0].t: expected a number"); unknown keys are
// errors too. It also loads what the file points at (object catalog, static map), so a Scenario
// is complete: every trajectory is in the map frame.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"
#include "scene_graph_tracker/relations/spatial_relations.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"
#include "scene_graph_tracker/simulation/building_map.hpp"

namespace sgt::sim {

class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PoseKey {
  double t = 0.0;  // seconds from the start of the scenario
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// Keyframed pose: position interpolated linearly, orientation by slerp (shortest arc); held
// before the first and after the last key.
class PoseTrajectory {
 public:
  PoseTrajectory() = default;
  // Keys need strictly increasing t; throws std::invalid_argument otherwise or when empty.
  explicit PoseTrajectory(std::vector<PoseKey> keys);
  Eigen::Isometry3d at(double t) const;
  const std::vector<PoseKey>& keys() const { return keys_; }
  bool empty() const { return keys_.empty(); }

 private:
  std::vector<PoseKey> keys_;
};

// Roll, pitch, yaw about fixed x, y, z (URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Quaterniond fromRpy(const Eigen::Vector3d& rpy);

// "object `id` is inside `container` from time `from` on": shorthand for a relation
// {subject: id, relation: in, object: container, from: from} (it is added to Scenario::relations).
struct InsideAnnotation {
  std::string container;  // id of another object
  double from = 0.0;
};

struct ObjectSpec {
  std::string id;
  std::string class_name;     // a class of the catalog
  PoseTrajectory trajectory;  // T_map_object
  std::optional<InsideAnnotation> inside;
  std::optional<Eigen::Vector3f> color;  // RGB 0..1; per-class default when absent
};

enum class Shape { Box, Cylinder, Sphere };

// Something the tracker does not know (a person, a cardboard box), centred at its pose.
struct DistractorSpec {
  std::string id;
  Shape shape = Shape::Box;
  Eigen::Vector3f size = Eigen::Vector3f::Constant(0.1f);  // box: edge lengths
  float radius = 0.05f;                                    // cylinder, sphere
  float height = 0.1f;                                     // cylinder (along its z)
  PoseTrajectory trajectory;                               // T_map_distractor
  Eigen::Vector3f color = Eigen::Vector3f(0.55f, 0.55f, 0.55f);
};

// Relation ground truth: `subject` stands in `relation` to `object` for t in [from, to).
struct RelationSpec {
  std::string subject;  // an object id
  relations::Relation relation = relations::Relation::On;
  std::string object;  // another object id, or kWorkbenchName when the scenario has a workbench
  double from = 0.0;
  double to = std::numeric_limits<double>::infinity();
  bool activeAt(double t) const { return t >= from && t < to; }
};

struct WorldSpec {
  enum class Kind { Building, Mesh, Urdf };
  Kind kind = Kind::Building;
  BuildingOptions building;  // Kind::Building
  std::string path;          // Kind::Mesh / Kind::Urdf, resolved
};

struct CameraSpec {
  PinholeModel model;
  Eigen::Isometry3d T_base_camera = Eigen::Isometry3d::Identity();  // optical frame in base_link
  double rate = 30.0;                                               // Hz
};

struct LidarSpec {
  SpinningLidarModel model;  // VLP-16, 16 x 1824
  Eigen::Isometry3d T_base_lidar = Eigen::Isometry3d::Identity();
  double rate = 10.0;  // Hz
};

struct NoiseSpec {
  double depth_sigma_at_1m = 0.0015;  // depth sigma = this * z^2 (m)
  double depth_edge_jump =
      0.04;  // m; a pixel whose 4-neighbour differs more loses its depth (0: off)
  double depth_max_incidence_deg =
      75;  // a ray hitting a surface more obliquely gets no depth (>= 90: off)
  double lidar_range_sigma = 0.008;      // m
  double odom_translation_sigma = 0.02;  // m per sqrt(m driven), each of x and y
  double odom_rotation_sigma = 0.01;     // rad per sqrt(m driven + rad turned)
  Eigen::Vector3d odom_initial_error =
      Eigen::Vector3d::Zero();  // dx, dy (m), dyaw (rad) of map->odom
};

struct DetectionSpec {
  bool enabled = true;
  int min_visible_pixels = 200;  // labelled depth pixels an object needs to be detected
  double sigma_t = 0.01;         // m, per axis of the camera frame
  double sigma_r_deg = 2.0;      // per axis (rotation vector)
  double miss_probability = 0.05;
  double false_positives_per_frame = 0.05;  // Poisson mean
};

struct Scenario {
  std::string file;  // as given to loadScenario
  double duration = 0.0;
  std::uint32_t seed = 0;
  double start_time = 1700000000.0;  // ROS time (s) of scenario time 0

  WorldSpec world;
  std::shared_ptr<const TriangleMesh> static_map;
  std::optional<Eigen::Vector3d> workbench;  // origin of `frame: workbench` (map frame)

  std::string catalog_path;  // resolved
  std::string mesh_dir;      // resolved mesh-directory override ("" = the catalog's own)
  std::shared_ptr<const ObjectCatalog> catalog;

  std::vector<ObjectSpec> objects;
  std::vector<DistractorSpec> distractors;
  std::vector<RelationSpec>
      relations;         // the `relations:` list, then the objects' `inside` annotations
  PoseTrajectory robot;  // T_map_base (planar: z = 0, yaw only)
  CameraSpec camera;
  LidarSpec lidar;
  NoiseSpec noise;
  DetectionSpec detections;

  const ObjectSpec* findObject(const std::string& id) const;
};

struct ScenarioLoadOptions {
  // Replaces the scenario's `mesh_dir` (e.g. ../shared/data/pbr_objects/meshes) when not empty.
  std::string mesh_dir_override;
};

Scenario loadScenario(const std::string& path, const ScenarioLoadOptions& options = {});

// Sensor frame times in nanoseconds from the start: round(k * 1e9 / rate) for k = 0, 1, ...
// while k / rate < duration (so rate x duration frames for whole numbers).
std::vector<std::int64_t> frameTimesNs(double rate, double duration);

}  // namespace sgt::sim
