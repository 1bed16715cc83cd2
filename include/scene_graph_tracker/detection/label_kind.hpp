// What a keypoint label is taken up to (render_dataset and sequence_to_dataset --labels):
//   object: the object's declared symmetries (its pose, as far as the object itself can tell);
//   cuboid: also a half turn of its box (the keypoints follow from the box's outline alone);
//   shape:  also every turn of its box that leaves its surface where it was, within
//           kShapeTwinFraction of its diameter: what a render of the shape alone can tell. A cube
//           has 24 such turns. A picture cube's faces differ, but renders without its pictures
//           cannot show which face is which, and labels that claim to would be learnt as noise.
#pragma once

#include <optional>
#include <string>

#include "scene_graph_tracker/scene/object_catalog.hpp"

namespace sgt::detection {

enum class LabelKind { kObject, kCuboid, kShape };

constexpr double kShapeTwinFraction = 0.005;

std::optional<LabelKind> parseLabelKind(const std::string& name);
const char* labelKindName(LabelKind kind);

// The symmetries `object`'s labels are taken up to: its declared ones, and for kShape its box's
// turns that look alike (nearTwinTurns). The half turns of kCuboid are applied by labelPose.
Symmetry labelSymmetry(const ObjectClass& object, LabelKind kind);

// The label pose of an object at T_camera_object: the canonical one among its poses that look
// alike to labels of `kind` (canonicalSymmetricPose, canonicalCuboidPose), `symmetry` from
// labelSymmetry.
Eigen::Isometry3d labelPose(const Eigen::Isometry3d& T_camera_object, const Symmetry& symmetry,
                            LabelKind kind);

}  // namespace sgt::detection
