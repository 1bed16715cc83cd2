#include "scene_graph_tracker/detection/label_kind.hpp"

#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/registration/twin_evidence.hpp"

namespace sgt::detection {

std::optional<LabelKind> parseLabelKind(const std::string& name) {
  if (name == "object") return LabelKind::kObject;
  if (name == "cuboid") return LabelKind::kCuboid;
  if (name == "shape") return LabelKind::kShape;
  return std::nullopt;
}

const char* labelKindName(LabelKind kind) {
  switch (kind) {
    case LabelKind::kCuboid:
      return "cuboid";
    case LabelKind::kShape:
      return "shape";
    case LabelKind::kObject:
      break;
  }
  return "object";
}

Symmetry labelSymmetry(const ObjectClass& object, LabelKind kind) {
  Symmetry s = object.symmetry;
  if (kind != LabelKind::kShape || !object.mesh) return s;
  RaycastScene scene;
  const MeshId mesh = scene.addMesh(object.mesh);
  for (const Eigen::Isometry3d& turn : nearTwinTurns(scene, mesh, object, kShapeTwinFraction))
    s.discrete.push_back(turn);
  return s;
}

Eigen::Isometry3d labelPose(const Eigen::Isometry3d& T_camera_object, const Symmetry& symmetry,
                            LabelKind kind) {
  return kind == LabelKind::kCuboid ? canonicalCuboidPose(T_camera_object, symmetry)
                                    : canonicalSymmetricPose(T_camera_object, symmetry);
}

}  // namespace sgt::detection
