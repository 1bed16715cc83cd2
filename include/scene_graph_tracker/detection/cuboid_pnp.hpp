// Cuboid PnP: an object's pose in the camera frame from its detected cuboid keypoints.
//
// The 2D keypoints (DOPE order, image pixels, with visibility) are matched to the class's 3D box
// corners + centre (cuboid.hpp). Points with visibility >= min_visibility inside the image count:
// >= 6 → iterative PnP (Levenberg-Marquardt from an EPnP start); 4–5 → AP3P on each 4-subset, the
// one with the smallest reprojection error over all used points, refined with LM; fewer → no pose.
// A solution with the object behind the camera or a large reprojection error is rejected.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "scene_graph_tracker/detection/cuboid.hpp"
#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt::detection {

struct PnpOptions {
  float min_visibility = 0.5f;
  double max_reprojection_px = 10.0;  // RMS over the used points
  double min_depth = 0.05;            // m; the object centre must be at least this far in front
};

enum class PnpStatus { Ok, TooFewPoints, SolverFailed, BehindCamera, LargeReprojection };
const char* pnpStatusName(PnpStatus s);

struct PnpResult {
  PnpStatus status = PnpStatus::TooFewPoints;
  Eigen::Isometry3d T_camera_object = Eigen::Isometry3d::Identity();
  double reprojection_rms_px = 0.0;
  int points_used = 0;
  bool ok() const { return status == PnpStatus::Ok; }
};

PnpResult solveCuboidPnp(const std::vector<Keypoint>& keypoints,
                         const std::array<Eigen::Vector3d, kCuboidKeypoints>& object_points,
                         const PinholeModel& camera, const PnpOptions& options = {});

}  // namespace sgt::detection
