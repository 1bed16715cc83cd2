// A keypoint detector's data set on disk, as render_dataset and sequence_to_dataset write it and
// evaluate_detector and scripts/train_detector.py read it:
//   DIR/images/000123.png   the image
//   DIR/labels/000123.txt   ultralytics pose format, one line per labelled object: class id, box
//                           of its visible pixels (centre, size; normalised), 9 cuboid keypoints
//                           (x, y, visibility 2 inside the image, 0 0 0 outside)
//   DIR/poses/000123.json   scene kind, camera K and per labelled object its class,
//                           T_camera_object and the label pose the keypoints were made from
//   DIR/depth/000123.png    optional: 16-bit depth in millimetres registered with the image
//                           (0 = no return); with it evaluate_detector gives the detector the depth
//                           as the nodes do (the PnP poses take their distance from it)
//   DIR/dataset.yaml        ultralytics style; `names` are the classes by label id
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scene_graph_tracker/detection/label_kind.hpp"
#include "scene_graph_tracker/evaluation/rgbd_sequence.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt {

struct DatasetObject {
  int class_id = 0;
  std::string class_name;
  int visible_pixels = 0;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // box of the visible pixels, inclusive
  Eigen::Isometry3d T_camera_object = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_label = Eigen::Isometry3d::Identity();  // the keypoints' pose
  Eigen::AlignedBox3d box;                                    // the class's cuboid
};

// Count and box (x0..y1) of the pixels of a row-major node image `width` wide that show `node`;
// the other fields stay default.
DatasetObject visibleBox(const std::vector<NodeId>& nodes, int width, NodeId node);

// "000123" for 123.
std::string datasetFrameName(std::size_t index);

// Writes labels/NAME.txt and poses/NAME.json of one image (the image itself is the caller's).
void writeDatasetLabels(const std::filesystem::path& dir, std::size_t index,
                        const std::string& scene_kind, const PinholeModel& camera,
                        const std::vector<DatasetObject>& objects);

// Writes depth/NAME.png: `depth_m` (metres along the optical axis, row-major, width x height)
// as 16-bit millimetres, 0 where there is no return (NaN, inf, <= 0 or beyond 65 m).
void writeDatasetDepth(const std::filesystem::path& dir, std::size_t index,
                       const std::vector<float>& depth_m, int width, int height);

// Writes dataset.yaml: `comment` (how the set was made), the paths and the class names by id.
void writeDatasetYaml(const std::filesystem::path& dir, const std::string& comment,
                      const std::vector<std::string>& names);

// Labels of a recorded sequence's frames from its given object poses. Class ids are the catalog's
// classes in its file's order (as render_dataset gives them). An object's box is that of its pixels
// in a ray cast of the catalog meshes at the given poses: the objects occlude each other, unknown
// things do not. Objects with fewer than `min_pixels` such pixels are not labelled.
class SequenceLabeller {
 public:
  // Throws std::runtime_error when an object of the sequence is not in the catalog.
  SequenceLabeller(const ObjectCatalog& catalog, const RgbdSequence& sequence,
                   detection::LabelKind labels, int min_pixels = 120);
  std::vector<DatasetObject> label(const RgbdSequence::Frame& frame);

 private:
  const ObjectCatalog& catalog_;
  const RgbdSequence& sequence_;
  detection::LabelKind labels_;
  std::map<std::string, Symmetry> label_symmetry_;
  int min_pixels_;
  RaycastScene scene_;
  std::map<std::string, int> class_id_;
  std::map<std::string, MeshId> mesh_;
  std::vector<std::string> node_name_;  // node k + 1 -> object
};

}  // namespace sgt
