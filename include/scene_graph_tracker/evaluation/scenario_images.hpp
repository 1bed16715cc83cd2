// Training images from scenarios (`render_dataset --scenarios DIR`): frames of scenario files at
// random times, rendered as the simulator renders a scenario's bag
// (`simulation/scenario_world.hpp`), so that the detector sees the scenes the suite shows it:
// stacks, containers, carried objects, occluders, the robot's views and distances. Generate them
// with a seed other than the suite's.
//
// One scenario world is loaded at a time: the images of a set are split into consecutive blocks,
// one per scenario file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "scene_graph_tracker/detection/label_kind.hpp"
#include "scene_graph_tracker/evaluation/keypoint_dataset.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"

namespace sgt {

namespace sim {
struct Scenario;
class ScenarioWorld;
}  // namespace sim

struct ScenarioImage {
  cv::Mat bgr;  // 8UC3
  PinholeModel camera;
  std::vector<DatasetObject> objects;  // the objects with at least min_pixels seen
};

// The scenario files of `dir`: every .yaml but generate_scenarios' index (scenarios.yaml), sorted.
std::vector<std::filesystem::path> scenarioFiles(const std::filesystem::path& dir);

class ScenarioImages {
 public:
  // `classes`: label id -> class name; `label_symmetry`: per label id, what its labels are taken up
  // to. A scenario object whose class is not among `classes` throws when its scenario is loaded.
  ScenarioImages(std::vector<std::filesystem::path> files, std::vector<std::string> classes,
                 std::vector<Symmetry> label_symmetry, detection::LabelKind labels,
                 std::string mesh_dir, int min_pixels);
  ~ScenarioImages();
  ScenarioImages(const ScenarioImages&) = delete;
  ScenarioImages& operator=(const ScenarioImages&) = delete;

  // Image `index` of a set of `count`: from scenario index * files / count, at a time drawn from
  // `seed` and `index` (the same arguments render the same image).
  ScenarioImage render(std::size_t index, std::size_t count, std::uint32_t seed);

 private:
  void load(std::size_t file);
  int classId(const std::string& name) const;

  std::vector<std::filesystem::path> files_;
  std::vector<std::string> classes_;
  std::vector<Symmetry> label_symmetry_;
  detection::LabelKind labels_;
  std::string mesh_dir_;
  int min_pixels_;
  std::size_t loaded_ = static_cast<std::size_t>(-1);
  std::unique_ptr<sim::Scenario> scenario_;  // outlives world_, which refers to it
  std::unique_ptr<sim::ScenarioWorld> world_;
  std::vector<int> object_class_;  // per scenario object: its label id
};

}  // namespace sgt
