#include "scene_graph_tracker/evaluation/keypoint_dataset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt {
namespace {

void writeMatrix(std::ostream& os, const Eigen::Isometry3d& T) {
  os << "[";
  for (int r = 0; r < 4; ++r) {
    os << (r ? ", [" : "[");
    for (int c = 0; c < 4; ++c) os << (c ? ", " : "") << T.matrix()(r, c);
    os << "]";
  }
  os << "]";
}

void writeLabelLine(std::ostream& txt, const PinholeModel& camera, const DatasetObject& o) {
  const double W = camera.width, H = camera.height;
  const auto proj = detection::projectCuboid(camera, o.T_label, o.box);
  txt << o.class_id << ' ' << (o.x0 + o.x1 + 1) / (2 * W) << ' ' << (o.y0 + o.y1 + 1) / (2 * H)
      << ' ' << (o.x1 - o.x0 + 1) / W << ' ' << (o.y1 - o.y0 + 1) / H;
  for (int k = 0; k < detection::kCuboidKeypoints; ++k) {
    if (proj.inside[k])
      txt << ' ' << (proj.uv[k].x() + 0.5) / W << ' ' << (proj.uv[k].y() + 0.5) / H << " 2";
    else
      txt << " 0 0 0";
  }
  txt << '\n';
}

}  // namespace

DatasetObject visibleBox(const std::vector<NodeId>& nodes, int width, NodeId node) {
  DatasetObject o;
  o.x0 = o.y0 = 1 << 30, o.x1 = o.y1 = -1;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i] != node) continue;
    const int u = static_cast<int>(i % static_cast<std::size_t>(width));
    const int v = static_cast<int>(i / static_cast<std::size_t>(width));
    ++o.visible_pixels;
    o.x0 = std::min(o.x0, u), o.y0 = std::min(o.y0, v);
    o.x1 = std::max(o.x1, u), o.y1 = std::max(o.y1, v);
  }
  return o;
}

std::string datasetFrameName(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu", index);
  return name;
}

void writeDatasetLabels(const std::filesystem::path& dir, std::size_t index,
                        const std::string& scene_kind, const PinholeModel& camera,
                        const std::vector<DatasetObject>& objects) {
  const std::string name = datasetFrameName(index);
  std::ofstream txt(dir / "labels" / (name + ".txt"));
  std::ofstream json(dir / "poses" / (name + ".json"));
  txt.precision(6), json.precision(9);
  json << "{\"scene\": \"" << scene_kind << "\", \"width\": " << camera.width
       << ", \"height\": " << camera.height << ", \"K\": [" << camera.fx << ", 0, " << camera.cx
       << ", 0, " << camera.fy << ", " << camera.cy << ", 0, 0, 1],\n \"objects\": [";
  bool first = true;
  for (const DatasetObject& o : objects) {
    writeLabelLine(txt, camera, o);
    json << (first ? "\n  " : ",\n  ") << "{\"class\": \"" << o.class_name
         << "\", \"class_id\": " << o.class_id << ", \"visible_pixels\": " << o.visible_pixels
         << ", \"T_camera_object\": ";
    writeMatrix(json, o.T_camera_object);
    json << ", \"T_camera_object_label\": ";
    writeMatrix(json, o.T_label);
    json << "}";
    first = false;
  }
  json << "]}\n";
}

void writeDatasetYaml(const std::filesystem::path& dir, const std::string& comment,
                      const std::vector<std::string>& names) {
  std::ofstream yaml(dir / "dataset.yaml");
  yaml << "# " << comment << "\npath: " << dir.string()
       << "\ntrain: images\nval: images\nkpt_shape: [9, 3]  # DOPE cuboid order\nnames:\n";
  for (std::size_t c = 0; c < names.size(); ++c) yaml << "  " << c << ": " << names[c] << "\n";
}

void writeDatasetDepth(const std::filesystem::path& dir, std::size_t index,
                       const std::vector<float>& depth_m, int width, int height) {
  if (depth_m.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("writeDatasetDepth: the depth image is not width x height");
  cv::Mat mm(height, width, CV_16UC1, cv::Scalar(0));
  for (std::size_t i = 0; i < depth_m.size(); ++i)
    if (std::isfinite(depth_m[i]) && depth_m[i] > 0.0f && depth_m[i] < 65.0f)
      mm.at<std::uint16_t>(static_cast<int>(i / width), static_cast<int>(i % width)) =
          static_cast<std::uint16_t>(std::lround(depth_m[i] * 1000.0f));
  std::filesystem::create_directories(dir / "depth");
  cv::imwrite((dir / "depth" / (datasetFrameName(index) + ".png")).string(), mm);
}

SequenceLabeller::SequenceLabeller(const ObjectCatalog& catalog, const RgbdSequence& sequence,
                                   detection::LabelKind labels, int min_pixels)
    : catalog_(catalog), sequence_(sequence), labels_(labels), min_pixels_(min_pixels) {
  const auto& ids = catalog.listed();
  for (const auto& name : sequence.objectNames()) {
    const auto it = std::find(ids.begin(), ids.end(), name);
    if (it == ids.end())
      throw std::runtime_error("the sequence's object '" + name + "' is not in the catalog");
    class_id_[name] = static_cast<int>(it - ids.begin());
    mesh_[name] = scene_.addMesh(catalog.get(name).mesh);
    label_symmetry_[name] = detection::labelSymmetry(catalog.get(name), labels);
  }
}

std::vector<DatasetObject> SequenceLabeller::label(const RgbdSequence::Frame& f) {
  for (std::size_t k = 0; k < node_name_.size(); ++k)
    scene_.removeInstance(static_cast<NodeId>(k + 1));
  node_name_.clear();
  for (const auto& [name, T] : f.T_camera_object) {
    node_name_.push_back(name);
    scene_.addInstance(static_cast<NodeId>(node_name_.size()), mesh_.at(name), T);
  }
  scene_.commit();
  const SimulatedScan scan =
      simulate(scene_, makeRays(sequence_.camera), Eigen::Isometry3d::Identity());
  std::vector<DatasetObject> out;
  for (std::size_t k = 0; k < node_name_.size(); ++k) {
    DatasetObject o = visibleBox(scan.node, scan.width, static_cast<NodeId>(k + 1));
    if (o.visible_pixels < min_pixels_) continue;
    const std::string& name = node_name_[k];
    const ObjectClass& oc = catalog_.get(name);
    o.class_id = class_id_.at(name), o.class_name = name;
    o.T_camera_object = f.T_camera_object.at(name);
    o.T_label = detection::labelPose(o.T_camera_object, label_symmetry_.at(name), labels_);
    o.box = oc.box.cast<double>();
    out.push_back(o);
  }
  return out;
}

}  // namespace sgt
