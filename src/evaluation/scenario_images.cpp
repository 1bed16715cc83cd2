#include "scene_graph_tracker/evaluation/scenario_images.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"
#include "scene_graph_tracker/simulation/scenario_world.hpp"

namespace sgt {

namespace fs = std::filesystem;

std::vector<fs::path> scenarioFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".yaml" &&
        e.path().filename() != "scenarios.yaml")
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::runtime_error("no scenario files (*.yaml) in " + dir.string());
  return files;
}

ScenarioImages::ScenarioImages(std::vector<fs::path> files, std::vector<std::string> classes,
                               std::vector<Symmetry> label_symmetry, detection::LabelKind labels,
                               std::string mesh_dir, int min_pixels)
    : files_(std::move(files)),
      classes_(std::move(classes)),
      label_symmetry_(std::move(label_symmetry)),
      labels_(labels),
      mesh_dir_(std::move(mesh_dir)),
      min_pixels_(min_pixels) {
  if (files_.empty()) throw std::invalid_argument("ScenarioImages: no scenario files");
  if (label_symmetry_.size() != classes_.size())
    throw std::invalid_argument("ScenarioImages: one label symmetry per class");
}

ScenarioImages::~ScenarioImages() = default;

int ScenarioImages::classId(const std::string& name) const {
  const auto it = std::find(classes_.begin(), classes_.end(), name);
  if (it == classes_.end())
    throw std::runtime_error(files_[loaded_].string() + ": class '" + name +
                             "' is not among the dataset's classes");
  return static_cast<int>(it - classes_.begin());
}

void ScenarioImages::load(std::size_t file) {
  if (file == loaded_) return;
  world_.reset();
  sim::ScenarioLoadOptions options;
  options.mesh_dir_override = mesh_dir_;
  scenario_ = std::make_unique<sim::Scenario>(sim::loadScenario(files_[file].string(), options));
  loaded_ = file;
  object_class_.clear();
  for (const auto& o : scenario_->objects) object_class_.push_back(classId(o.class_name));
  world_ = std::make_unique<sim::ScenarioWorld>(*scenario_);
}

ScenarioImage ScenarioImages::render(std::size_t index, std::size_t count, std::uint32_t seed) {
  load(std::min(files_.size() - 1, index * files_.size() / std::max<std::size_t>(count, 1)));
  std::mt19937 rng(static_cast<std::uint32_t>(seed * 2246822519u + index * 3266489917u + 7u));
  ScenarioImage image;
  const double t = std::uniform_real_distribution<double>(0.0, scenario_->duration)(rng);
  image.camera = scenario_->camera.model;
  const sim::CameraFrame f = world_->renderCamera(t, index);
  cv::cvtColor(cv::Mat(image.camera.height, image.camera.width, CV_8UC3,
                       const_cast<std::uint8_t*>(f.rgb.data())),
               image.bgr, cv::COLOR_RGB2BGR);
  for (std::size_t i = 0; i < scenario_->objects.size(); ++i) {
    DatasetObject o = visibleBox(f.seen, image.camera.width, world_->objectNode(i));
    if (o.visible_pixels < min_pixels_) continue;
    o.class_id = object_class_[i];
    o.class_name = classes_[o.class_id];
    o.T_camera_object = f.T_map_camera.inverse() * f.T_map_objects[i];
    o.T_label = detection::labelPose(o.T_camera_object, label_symmetry_[o.class_id], labels_);
    o.box = scenario_->catalog->get(o.class_name).box.cast<double>();
    image.objects.push_back(std::move(o));
  }
  return image;
}

}  // namespace sgt
