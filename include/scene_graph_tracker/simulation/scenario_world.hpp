// A scenario brought to life: the ray-casting scene with the static map, the catalog objects and
// the distractors, moved to any time of the scenario, and what the robot's sensors measure then
// (rendered RGB, noisy registered depth, a noisy VLP-16 scan, per-measurement labels), the
// drifting odometry and simulated detections. ROS-free; the bag writer turns frames into messages.
//
// Deterministic: every random draw comes from a generator seeded by the scenario's seed, the kind
// of draw and the frame index, so a frame does not depend on which frames were made before it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/simulation/rgb_render.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"

namespace sgt::sim {

// Per-measurement labels of /ground_truth/depth_labels and /ground_truth/velodyne_labels.
enum Label : std::uint8_t {
  kLabelNoReturn = 0,
  kLabelStaticMap = 1,
  kLabelObject = 2,      // a catalog object
  kLabelDistractor = 3,  // not in the catalog
};

struct CameraFrame {
  double t = 0.0;
  Eigen::Isometry3d T_map_base, T_map_camera;  // true poses
  std::vector<std::uint8_t> rgb;               // rgb8, width x height x 3
  std::vector<float> depth;                    // z in metres, NaN = no return (noisy)
  std::vector<std::uint8_t> labels;            // Label per pixel; kLabelNoReturn where depth is NaN
  std::vector<NodeId> seen;  // node the RGB shows at each pixel, depth or not (kNoNode: none)
  std::vector<Eigen::Isometry3d> T_map_objects;  // per scenario object
  std::vector<int> visible_pixels;               // per scenario object: valid depth pixels on it
};

struct LidarFrame {
  double t = 0.0;
  Eigen::Isometry3d T_map_base, T_map_lidar;
  std::vector<float> range;      // along the model's rays, NaN = no return (noisy)
  std::vector<float> intensity;  // 100 * |cos(incidence angle)|, 0 without return
  std::vector<std::uint8_t> labels;
};

struct Hypothesis {
  std::string class_name;
  Eigen::Isometry3d T_camera_object;
  float score = 0.0f;
  int object = -1;  // index into Scenario::objects; -1 for a false positive
};

class ScenarioWorld {
 public:
  explicit ScenarioWorld(const Scenario& scenario);  // keeps a reference to `scenario`
  ~ScenarioWorld();
  ScenarioWorld(const ScenarioWorld&) = delete;
  ScenarioWorld& operator=(const ScenarioWorld&) = delete;

  const Scenario& scenario() const { return s_; }
  const SensorRays& cameraRays() const { return *camera_rays_; }
  const SensorRays& lidarRays() const { return *lidar_rays_; }
  NodeId objectNode(std::size_t i) const { return static_cast<NodeId>(kFirstObjectNode + i); }
  NodeId distractorNode(std::size_t i) const {
    return static_cast<NodeId>(kFirstDistractorNode + i);
  }
  static constexpr NodeId kStaticMapNode = 1;
  static constexpr NodeId kFirstObjectNode = 100;
  static constexpr NodeId kFirstDistractorNode = 100000;
  Label labelOf(NodeId node) const;

  // True base pose (map -> base_link).
  Eigen::Isometry3d basePose(double t) const { return s_.robot.at(t); }
  // Odometry (odom -> base_link): starts at the true start pose (odom coincides with map up to the
  // initial error) and integrates the true motion with random-walk noise.
  Eigen::Isometry3d odometry(double t) const;
  // map -> odom: constant and identity-ish: the identity moved by the configured initial error,
  // applied in the robot's start frame (T0 * E * T0^-1), so map -> odom -> base_link at t = 0 is
  // the true start pose times E. map -> odom -> base_link is the odometry prior a localizer
  // corrects; it drifts away from basePose(t).
  Eigen::Isometry3d mapToOdom() const { return T_map_odom_; }

  // Moves every object and distractor to time t (each frame does this itself).
  void setTime(double t);
  CameraFrame renderCamera(double t, std::uint64_t frame_index);
  LidarFrame scanLidar(double t, std::uint64_t frame_index);
  // Ground truth of each object with >= min_visible_pixels, disturbed by the configured noise,
  // minus misses, plus false positives (a random class upright on a random visible surface).
  std::vector<Hypothesis> detect(const CameraFrame& frame, std::uint64_t frame_index) const;

 private:
  void simulateOdometry();

  const Scenario& s_;
  std::unique_ptr<RaycastScene> scene_;
  std::shared_ptr<const SensorRays> camera_rays_, lidar_rays_;
  NodeColours colours_;
  RenderStyle style_;
  std::vector<double> odom_x_, odom_y_, odom_yaw_;  // sampled every kOdomStep
  Eigen::Isometry3d T_map_odom_ = Eigen::Isometry3d::Identity();
  static constexpr double kOdomStep = 0.01;
};

}  // namespace sgt::sim
