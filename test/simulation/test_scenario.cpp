// Scenario files: a valid file parses to the expected values, keyframes interpolate (linear
// position, slerp, held after the end), broken files name the file, the line and the field; the
// scenario world renders consistent frames and detections.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "scene_graph_tracker/simulation/scenario.hpp"
#include "scene_graph_tracker/simulation/scenario_world.hpp"
#include "support.hpp"

namespace sgt::sim {
namespace {

using ::testing::HasSubstr;

// A small valid scenario; tests replace single lines to break it.
const char* kValid = R"(duration: 2.5
seed: 11
world:
  building: {length_x: 10, length_y: 8, rooms_x: 1, rooms_y: 1, target_triangles: 0, tile_size: 0.5, furniture: false}
catalog: package://scene_graph_tracker/config/objects.yaml
objects:
  - id: klt_1
    class: klt
    frame: workbench
    keyframes:
      - {t: 0, xyz: [0.3, -0.1, 0.0745], rpy_deg: [0, 0, 10]}
  - id: relay_1
    class: relay
    inside: {container: klt_1, from: 2.0}
    color: [0.1, 0.9, 0.2]
    keyframes:
      - {t: 1.0, xyz: [3.0, 2.0, 0.9]}
      - {t: 2.0, xyz: [3.2, 2.2, 0.8], rpy: [0, 0, 1.0]}
distractors:
  - id: person
    shape: cylinder
    radius: 0.25
    height: 1.75
    keyframes:
      - {t: 0, xyz: [5, 5, 0.875]}
  - {id: box_1, shape: box, size: [0.1, 0.2, 0.3], color: [0.5, 0.4, 0.3], keyframes: [{t: 0, xyz: [4, 4, 0.15]}]}
relations:
  - {subject: klt_1, relation: on, object: workbench, to: 1.5}
  - subject: klt_1
    relation: left_of
    object: relay_1
    from: 0.5
    to: 2.0
robot:
  frame: workbench
  keyframes:
    - {t: 0, xy: [0.0, 2.0], yaw_deg: -90}
    - {t: 2, xy: [0.0, 1.1], yaw: -1.5707963267948966}
camera:
  width: 64
  height: 48
  fx: 52.5
  fy: 52.5
  rate: 15
  mount: {xyz: [0.1, 0.0, 1.25], rpy_deg: [0, 20, 0]}
lidar:
  rate: 5
  mount: {xyz: [0.0, 0.0, 0.9]}
noise:
  depth_sigma_at_1m: 0.002
  lidar_range_sigma: 0.01
  odometry: {translation_sigma: 0.03, initial_error: [0.1, 0.0, 0.0]}
detections:
  sigma_t: 0.02
  miss_probability: 0.1
  false_positives_per_frame: 0.5
)";

// 1-based number of the first line containing `needle`.
int lineOf(const std::string& text, const std::string& needle) {
  std::istringstream ss(text);
  std::string line;
  for (int n = 1; std::getline(ss, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  ADD_FAILURE() << "no line contains '" << needle << "'";
  return -1;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// Loads `text` as `name`; returns the ScenarioError message ("" when it loaded).
std::string errorOf(const std::string& name, const std::string& text) {
  const std::string path = test::writeFile(name, text);
  try {
    loadScenario(path);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(Scenario, ValidFileParsesToTheExpectedValues) {
  const std::string path = test::writeFile("valid.yaml", kValid);
  const Scenario s = loadScenario(path);
  EXPECT_EQ(s.file, path);
  EXPECT_DOUBLE_EQ(s.duration, 2.5);
  EXPECT_EQ(s.seed, 11u);
  EXPECT_EQ(s.world.kind, WorldSpec::Kind::Building);
  EXPECT_FLOAT_EQ(s.world.building.length_x, 10.0f);
  EXPECT_FALSE(s.world.building.furniture);
  ASSERT_TRUE(s.workbench.has_value());
  ASSERT_TRUE(s.static_map && !s.static_map->empty());
  ASSERT_TRUE(s.catalog && s.catalog->contains("klt"));
  const Eigen::Vector3d wb = *s.workbench;

  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].id, "klt_1");
  EXPECT_EQ(s.objects[0].class_name, "klt");
  const Eigen::Isometry3d T_klt = s.objects[0].trajectory.at(0.0);
  EXPECT_TRUE(T_klt.translation().isApprox(wb + Eigen::Vector3d(0.3, -0.1, 0.0745), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(T_klt.linear()).angle(), 10.0 * M_PI / 180.0, 1e-9);
  EXPECT_FALSE(s.objects[0].inside.has_value());
  ASSERT_TRUE(s.objects[1].inside.has_value());
  EXPECT_EQ(s.objects[1].inside->container, "klt_1");
  EXPECT_DOUBLE_EQ(s.objects[1].inside->from, 2.0);
  // The `relations:` list, then the `inside` annotation as a relation.
  ASSERT_EQ(s.relations.size(), 3u);
  EXPECT_EQ(s.relations[0].subject, "klt_1");
  EXPECT_EQ(s.relations[0].relation, relations::Relation::On);
  EXPECT_EQ(s.relations[0].object, "workbench");
  EXPECT_DOUBLE_EQ(s.relations[0].from, 0.0);
  EXPECT_DOUBLE_EQ(s.relations[0].to, 1.5);
  EXPECT_TRUE(s.relations[0].activeAt(1.0));
  EXPECT_FALSE(s.relations[0].activeAt(1.5));
  EXPECT_EQ(s.relations[1].relation, relations::Relation::LeftOf);
  EXPECT_EQ(s.relations[1].object, "relay_1");
  EXPECT_DOUBLE_EQ(s.relations[1].from, 0.5);
  EXPECT_EQ(s.relations[2].subject, "relay_1");
  EXPECT_EQ(s.relations[2].relation, relations::Relation::In);
  EXPECT_EQ(s.relations[2].object, "klt_1");
  EXPECT_DOUBLE_EQ(s.relations[2].from, 2.0);
  EXPECT_TRUE(std::isinf(s.relations[2].to));
  ASSERT_TRUE(s.objects[1].color.has_value());
  EXPECT_TRUE(s.objects[1].color->isApprox(Eigen::Vector3f(0.1f, 0.9f, 0.2f)));
  EXPECT_EQ(s.objects[1].trajectory.keys().size(), 2u);
  EXPECT_TRUE(s.objects[1].trajectory.at(1.0).translation().isApprox(
      Eigen::Vector3d(3.0, 2.0, 0.9)));  // map frame

  ASSERT_EQ(s.distractors.size(), 2u);
  EXPECT_EQ(s.distractors[0].shape, Shape::Cylinder);
  EXPECT_FLOAT_EQ(s.distractors[0].radius, 0.25f);
  EXPECT_FLOAT_EQ(s.distractors[0].height, 1.75f);
  EXPECT_EQ(s.distractors[1].shape, Shape::Box);
  EXPECT_TRUE(s.distractors[1].size.isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.3f)));
  EXPECT_TRUE(s.distractors[1].color.isApprox(Eigen::Vector3f(0.5f, 0.4f, 0.3f)));

  const Eigen::Isometry3d T_base0 = s.robot.at(0.0), T_base2 = s.robot.at(2.0);
  EXPECT_TRUE(T_base0.translation().isApprox(Eigen::Vector3d(wb.x(), wb.y() + 2.0, 0.0), 1e-12));
  EXPECT_TRUE(T_base2.translation().isApprox(Eigen::Vector3d(wb.x(), wb.y() + 1.1, 0.0), 1e-12));
  EXPECT_TRUE(
      (T_base0.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-9));

  EXPECT_EQ(s.camera.model.width, 64);
  EXPECT_EQ(s.camera.model.height, 48);
  EXPECT_DOUBLE_EQ(s.camera.model.fx, 52.5);
  EXPECT_DOUBLE_EQ(s.camera.model.cx, 31.5);  // default: image centre
  EXPECT_DOUBLE_EQ(s.camera.rate, 15.0);
  // rpy_deg [0, 20, 0]: the body pitched 20 deg down; the optical z axis is the body's x.
  const Eigen::Isometry3d& T_bc = s.camera.T_base_camera;
  EXPECT_TRUE(T_bc.translation().isApprox(Eigen::Vector3d(0.1, 0.0, 1.25)));
  const Eigen::Vector3d z_opt = T_bc.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(z_opt.isApprox(
      Eigen::Vector3d(std::cos(20 * M_PI / 180), 0, -std::sin(20 * M_PI / 180)), 1e-9));
  EXPECT_TRUE((T_bc.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-9));
  EXPECT_DOUBLE_EQ(s.lidar.rate, 5.0);
  EXPECT_TRUE(s.lidar.T_base_lidar.translation().isApprox(Eigen::Vector3d(0, 0, 0.9)));
  EXPECT_EQ(s.lidar.model.columns, 1824);

  EXPECT_DOUBLE_EQ(s.noise.depth_sigma_at_1m, 0.002);
  EXPECT_DOUBLE_EQ(s.noise.depth_edge_jump, NoiseSpec{}.depth_edge_jump);  // default kept
  EXPECT_DOUBLE_EQ(s.noise.lidar_range_sigma, 0.01);
  EXPECT_DOUBLE_EQ(s.noise.odom_translation_sigma, 0.03);
  EXPECT_DOUBLE_EQ(s.noise.odom_rotation_sigma, NoiseSpec{}.odom_rotation_sigma);
  EXPECT_TRUE(s.noise.odom_initial_error.isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_DOUBLE_EQ(s.detections.sigma_t, 0.02);
  EXPECT_DOUBLE_EQ(s.detections.miss_probability, 0.1);
  EXPECT_DOUBLE_EQ(s.detections.false_positives_per_frame, 0.5);
  EXPECT_EQ(s.detections.min_visible_pixels, 200);
}

TEST(Scenario, LookAtMountPointsTheCameraAtTheTarget) {
  const std::string text =
      replaced(kValid, "mount: {xyz: [0.1, 0.0, 1.25], rpy_deg: [0, 20, 0]}",
               "mount: {xyz: [0.1, 0.0, 1.25], look_at: [0, 0, 0], look_at_frame: workbench}");
  const Scenario s = loadScenario(test::writeFile("look_at.yaml", text));
  // At the last robot keyframe the optical axis goes through the workbench origin.
  const Eigen::Isometry3d T_map_cam = s.robot.at(2.0) * s.camera.T_base_camera;
  const Eigen::Vector3d to_target = (*s.workbench - T_map_cam.translation()).normalized();
  EXPECT_GT((T_map_cam.linear() * Eigen::Vector3d::UnitZ()).dot(to_target), 1.0 - 1e-9);
  EXPECT_TRUE(s.camera.T_base_camera.translation().isApprox(Eigen::Vector3d(0.1, 0.0, 1.25), 1e-9));
}

TEST(Scenario, KeyframesInterpolateAndHold) {
  PoseKey a, b, c;
  a.t = 1.0, a.position = Eigen::Vector3d(0, 0, 0);
  b.t = 3.0, b.position = Eigen::Vector3d(2, -4, 6),
  b.orientation = fromRpy(Eigen::Vector3d(0, 0, 1.2));
  c.t = 4.0, c.position = Eigen::Vector3d(2, -4, 7),
  c.orientation = fromRpy(Eigen::Vector3d(0.4, 0, 1.2));
  const PoseTrajectory traj({a, b, c});
  // Held before the first key.
  EXPECT_TRUE(traj.at(0.0).isApprox(traj.at(1.0)));
  EXPECT_TRUE(traj.at(-5.0).translation().isZero());
  // Position linear, orientation slerp (half the angle at the middle).
  const Eigen::Isometry3d mid = traj.at(2.0);
  EXPECT_TRUE(mid.translation().isApprox(Eigen::Vector3d(1, -2, 3), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(mid.linear()).angle(), 0.6, 1e-12);
  EXPECT_TRUE((Eigen::AngleAxisd(mid.linear()).axis()).isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
  const Eigen::Isometry3d q = traj.at(1.5);
  EXPECT_TRUE(q.translation().isApprox(Eigen::Vector3d(0.5, -1, 1.5), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(q.linear()).angle(), 0.3, 1e-12);
  // Exactly at a key, and between the last two keys: a rotation about x (roll) on top of the yaw.
  EXPECT_TRUE(traj.at(3.0).linear().isApprox(b.orientation.toRotationMatrix(), 1e-12));
  const Eigen::Matrix3d R_rel =
      b.orientation.toRotationMatrix().transpose() * traj.at(3.5).linear();
  EXPECT_NEAR(Eigen::AngleAxisd(R_rel).angle(), 0.2, 1e-9);
  // Held after the last key.
  EXPECT_TRUE(traj.at(4.0).isApprox(traj.at(100.0)));
  EXPECT_TRUE(traj.at(100.0).translation().isApprox(Eigen::Vector3d(2, -4, 7)));
  // Slerp takes the short way: from +170 deg to -170 deg of yaw passes 180, not 0.
  PoseKey d, e;
  d.t = 0.0, d.orientation = fromRpy(Eigen::Vector3d(0, 0, 170 * M_PI / 180));
  e.t = 1.0, e.orientation = fromRpy(Eigen::Vector3d(0, 0, -170 * M_PI / 180));
  EXPECT_NEAR(Eigen::AngleAxisd(PoseTrajectory({d, e}).at(0.5).linear()).angle(), M_PI, 1e-9);
  EXPECT_THROW(PoseTrajectory({b, a}), std::invalid_argument);
}

TEST(Scenario, FrameTimesFollowTheRate) {
  const auto cam = frameTimesNs(30.0, 20.0);
  ASSERT_EQ(cam.size(), 600u);
  EXPECT_EQ(cam[3], 100000000);
  EXPECT_EQ(cam.back(), 19966666667);
  const auto lidar = frameTimesNs(10.0, 20.0);
  ASSERT_EQ(lidar.size(), 200u);
  EXPECT_EQ(lidar[1], cam[3]);  // LiDAR stamps coincide with camera stamps
  EXPECT_EQ(frameTimesNs(10.0, 1.05).size(), 11u);
}

// Each broken file: the message names the file, the line and the field.
struct Broken {
  const char* name;
  const char* from;     // line content replaced ...
  const char* to;       // ... by this
  const char* line_of;  // the error's line is the first line containing this (after the change) ...
  const char* message;  // "<field>: <problem>"
  int line_offset = 0;  // ... plus this
};

TEST(Scenario, BrokenFilesNameFileLineAndField) {
  const Broken cases[] = {
      {"not_a_number.yaml", "{t: 1.0, xyz: [3.0, 2.0, 0.9]}", "{t: soon, xyz: [3.0, 2.0, 0.9]}",
       "t: soon", "objects[1].keyframes[0].t: expected a number"},
      {"missing_class.yaml", "    class: relay\n", "", "- id: relay_1",
       "objects[1].class: required field is missing"},
      {"missing_duration.yaml", "duration: 2.5\n", "", "seed: 11",
       "duration: required field is missing"},
      {"unknown_key.yaml", "    color: [0.1, 0.9, 0.2]", "    colour: [0.1, 0.9, 0.2]", "colour:",
       "objects[1].colour: unknown key (expected one of: id, class, frame, keyframes, inside, "
       "color)"},
      {"unknown_top_key.yaml", "seed: 11", "sed: 11", "sed: 11",
       "sed: unknown key (expected one of: duration, seed,"},
      {"unknown_class.yaml", "    class: relay", "    class: hammer", "class: hammer",
       "objects[1].class: unknown class 'hammer' (catalog "},
      {"short_list.yaml", "{t: 2.0, xyz: [3.2, 2.2, 0.8]", "{t: 2.0, xyz: [3.2, 2.2]",
       "xyz: [3.2, 2.2]", "objects[1].keyframes[1].xyz: expected a list of 3 numbers, got 2"},
      {"long_list.yaml", "size: [0.1, 0.2, 0.3]", "size: [0.1, 0.2, 0.3, 0.4]",
       "size: [0.1, 0.2, 0.3, 0.4]", "distractors[1].size: expected a list of 3 numbers, got 4"},
      {"robot_xy.yaml", "xy: [0.0, 1.1]", "xy: [0.0, 1.1, 0.0]", "xy: [0.0, 1.1, 0.0]",
       "robot.keyframes[1].xy: expected a list of 2 numbers, got 3"},
      {"bad_shape.yaml", "shape: cylinder", "shape: cone", "shape: cone",
       "distractors[0].shape: unknown shape 'cone' (expected box, cylinder or sphere)"},
      {"time_order.yaml", "{t: 2.0, xyz: [3.2", "{t: 0.5, xyz: [3.2", "t: 0.5",
       "objects[1].keyframes[1].t: keyframe times must increase (previous keyframe has t = 1)"},
      {"bad_container.yaml", "container: klt_1", "container: klt_9", "container: klt_9",
       "objects[1].inside.container: 'klt_9' is not the id of another object"},
      {"bad_rate.yaml", "  rate: 15", "  rate: -15", "rate: -15",
       "camera.rate: expected a number > 0"},
      {"bad_probability.yaml", "miss_probability: 0.1", "miss_probability: 1.5", "miss_probability",
       "detections.miss_probability: expected a number in 0..1"},
      {"bad_frame.yaml", "    frame: workbench\n    keyframes:\n      - {t: 0, xyz: [0.3",
       "    frame: bench\n    keyframes:\n      - {t: 0, xyz: [0.3", "frame: bench",
       "objects[0].frame: unknown frame 'bench' (expected map or workbench)"},
      {"duplicate_id.yaml", "- id: relay_1", "- id: klt_1", "    class: relay",
       "objects[1].id: duplicate id 'klt_1'", -1},
      {"bad_relation.yaml", "relation: on,", "relation: beside,", "relation: beside",
       "relations[0].relation: unknown relation 'beside' (expected on, in, left_of, right_of, "
       "in_front_of, behind, above or below)"},
      {"bad_relation_object.yaml", "    object: relay_1", "    object: relay_9", "object: relay_9",
       "relations[1].object: 'relay_9' is not the id of an object or workbench"},
      {"bad_relation_subject.yaml", "{subject: klt_1,", "{subject: person,", "subject: person",
       "relations[0].subject: 'person' is not the id of an object"},
      {"bad_relation_key.yaml", "    to: 2.0", "    until: 2.0", "until: 2.0",
       "relations[1].until: unknown key (expected one of: subject, relation, object, from, to)"},
      {"bad_relation_to.yaml", "    to: 2.0", "    to: 0.2", "to: 0.2",
       "relations[1].to: expected a time after from (0.5)"},
      {"syntax.yaml", "    radius: 0.25", "    radius: [0.25", "radius: [0.25",
       "YAML syntax error"},
      // make fuzz (config): a tiny tile overflowed the quad count (and memory), a huge size left
      // float range (a map of infinite vertices).
      {"tiny_tile.yaml", "tile_size: 0.5", "tile_size: 0.00001", "tile_size: 0.00001",
       "world.building.tile_size: tile_size 1e-05 m makes "},
      {"huge_building.yaml", "length_x: 10", "length_x: 1e39", "length_x: 1e39",
       "world.building.length_x: expected at most 1000 (m)"},
  };
  for (const Broken& c : cases) {
    const std::string text = replaced(kValid, c.from, c.to);
    const std::string message = errorOf(c.name, text);
    int line = lineOf(text, c.line_of) + c.line_offset;
    if (std::string(c.name) == "syntax.yaml") line = -1;  // where the parser notices: checked below
    const std::string expected =
        std::string(c.name) + ":" + std::to_string(line) + ": " + c.message;
    if (line > 0)
      EXPECT_THAT(message, HasSubstr(expected)) << c.name;
    else
      EXPECT_THAT(message, HasSubstr(c.message)) << c.name;
    EXPECT_THAT(message, HasSubstr(c.name));
  }
  EXPECT_THAT(errorOf("syntax.yaml", replaced(kValid, "    radius: 0.25", "    radius: [0.25")),
              ::testing::MatchesRegex(".*syntax\\.yaml:[0-9]+: YAML syntax error.*"));
  EXPECT_THAT(errorOf("empty.yaml", ""),
              HasSubstr("empty.yaml:1: expected a map of scenario fields"));
  const std::string missing = (std::string(test::tempDir()) + "/does_not_exist.yaml");
  try {
    loadScenario(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const ScenarioError& e) {
    EXPECT_THAT(e.what(), HasSubstr("does_not_exist.yaml: cannot read the file"));
  }
}

TEST(Scenario, WorldRendersConsistentFramesAndDetections) {
  std::string text =
      replaced(kValid, "false_positives_per_frame: 0.5", "false_positives_per_frame: 3");
  text = replaced(text, "miss_probability: 0.1", "miss_probability: 0.0\n  min_visible_pixels: 5");
  text = replaced(text, "rpy_deg: [0, 20, 0]}", "rpy_deg: [0, 30, 0]}");
  const Scenario s = loadScenario(test::writeFile("world.yaml", text));
  ScenarioWorld world(s);
  const CameraFrame f = world.renderCamera(2.0, 60);
  const std::size_t n = static_cast<std::size_t>(s.camera.model.width) * s.camera.model.height;
  ASSERT_EQ(f.depth.size(), n);
  ASSERT_EQ(f.labels.size(), n);
  ASSERT_EQ(f.rgb.size(), 3 * n);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(f.labels[i] == kLabelNoReturn, !std::isfinite(f.depth[i])) << i;
    EXPECT_LE(f.labels[i], kLabelDistractor);
    valid += std::isfinite(f.depth[i]);
  }
  EXPECT_GT(valid, n / 2);
  EXPECT_GT(f.visible_pixels[0], 5) << "the KLT is in view";
  EXPECT_TRUE(f.T_map_objects[0].isApprox(s.objects[0].trajectory.at(2.0)));

  // Detections: the visible KLT (no misses), false positives in front of the camera.
  const auto hyps = world.detect(f, 60);
  int klt = 0;
  for (const Hypothesis& h : hyps) {
    EXPECT_GE(h.score, 0.0f);
    EXPECT_LE(h.score, 1.0f);
    if (h.object == 0) {
      ++klt;
      const Eigen::Isometry3d truth = f.T_map_camera.inverse() * f.T_map_objects[0];
      EXPECT_LT((h.T_camera_object.translation() - truth.translation()).norm(),
                6 * 0.02 * std::sqrt(3.0));
    } else if (h.object < 0) {
      EXPECT_GT(h.T_camera_object.translation().z(), 0.0);
      const auto px = s.camera.model.project(h.T_camera_object.translation());
      ASSERT_TRUE(px.has_value());
      EXPECT_TRUE(s.catalog->contains(h.class_name));
    }
  }
  EXPECT_EQ(klt, 1);

  // Deterministic: a second world gives the same frame and the same detections.
  ScenarioWorld again(s);
  const CameraFrame g = again.renderCamera(2.0, 60);
  EXPECT_EQ(0, std::memcmp(f.depth.data(), g.depth.data(), n * sizeof(float)));
  EXPECT_EQ(f.rgb, g.rgb);
  EXPECT_EQ(again.detect(g, 60).size(), hyps.size());

  // LiDAR: labels exactly where there are returns.
  const LidarFrame l = world.scanLidar(1.0, 5);
  ASSERT_EQ(l.range.size(), 16u * 1824u);
  for (std::size_t i = 0; i < l.range.size(); ++i)
    EXPECT_EQ(l.labels[i] == kLabelNoReturn, !std::isfinite(l.range[i])) << i;

  // Odometry: the true start pose at the start, drifts only while the robot moves; the prior
  // map -> odom -> base_link starts at the start pose moved by the initial error (0.1 m forward).
  EXPECT_TRUE(world.odometry(0.0).isApprox(s.robot.at(0.0)));
  EXPECT_TRUE(world.odometry(2.0).isApprox(world.odometry(2.4)));
  EXPECT_LT((world.odometry(2.0).translation() - s.robot.at(2.0).translation()).norm(), 0.2);
  EXPECT_GT((world.odometry(2.0).translation() - s.robot.at(2.0).translation()).norm(),
            1e-6);  // it drifts
  const Eigen::Isometry3d prior0 = world.mapToOdom() * world.odometry(0.0);
  EXPECT_TRUE(prior0.translation().isApprox(s.robot.at(0.0) * Eigen::Vector3d(0.1, 0, 0), 1e-9));
  EXPECT_TRUE(prior0.linear().isApprox(s.robot.at(0.0).linear(), 1e-9));
}

}  // namespace
}  // namespace sgt::sim
