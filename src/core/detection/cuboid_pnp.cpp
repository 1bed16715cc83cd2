#include "scene_graph_tracker/detection/cuboid_pnp.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace sgt::detection {

const char* pnpStatusName(PnpStatus s) {
  switch (s) {
    case PnpStatus::Ok:
      return "ok";
    case PnpStatus::TooFewPoints:
      return "too few points";
    case PnpStatus::SolverFailed:
      return "solver failed";
    case PnpStatus::BehindCamera:
      return "behind the camera";
    case PnpStatus::LargeReprojection:
      return "large reprojection error";
  }
  return "?";
}

namespace {

struct Correspondences {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
};

// OpenCV's camera matrix and distortion coefficients (empty: none) of a pinhole model.
struct Intrinsics {
  cv::Mat K, D;
  explicit Intrinsics(const PinholeModel& c)
      : K((cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1)) {
    if (c.distorted()) D = cv::Mat(c.distortion, true).reshape(1, 1);
  }
};

double reprojectionRms(const Correspondences& c, const cv::Mat& rvec, const cv::Mat& tvec,
                       const Intrinsics& in) {
  std::vector<cv::Point2d> projected;
  cv::projectPoints(c.object, rvec, tvec, in.K, in.D, projected);
  double sum = 0.0;
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const cv::Point2d d = projected[i] - c.image[i];
    sum += d.dot(d);
  }
  return std::sqrt(sum / static_cast<double>(projected.size()));
}

// AP3P on every 4-subset of 4–5 points; the solution that reprojects all points best.
bool solveFewPoints(const Correspondences& c, const Intrinsics& in, cv::Mat& rvec, cv::Mat& tvec) {
  const std::size_t n = c.object.size();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t skip = 0; skip < (n == 4 ? 1 : n); ++skip) {
    Correspondences sub;
    for (std::size_t i = 0; i < n; ++i) {
      if (n == 5 && i == skip) continue;
      sub.object.push_back(c.object[i]);
      sub.image.push_back(c.image[i]);
    }
    cv::Mat r, t;
    try {
      if (!cv::solvePnP(sub.object, sub.image, in.K, in.D, r, t, false, cv::SOLVEPNP_AP3P))
        continue;
    } catch (const cv::Exception&) {
      continue;
    }
    const double e = reprojectionRms(c, r, t, in);
    if (e < best) {
      best = e;
      rvec = r;
      tvec = t;
    }
  }
  if (!std::isfinite(best)) return false;
  cv::solvePnPRefineLM(c.object, c.image, in.K, in.D, rvec, tvec);
  return true;
}

}  // namespace

PnpResult solveCuboidPnp(const std::vector<Keypoint>& keypoints,
                         const std::array<Eigen::Vector3d, kCuboidKeypoints>& object_points,
                         const PinholeModel& camera, const PnpOptions& options) {
  PnpResult result;
  Correspondences c;
  for (std::size_t k = 0; k < keypoints.size() && k < object_points.size(); ++k) {
    const Keypoint& kp = keypoints[k];
    if (!(kp.visibility >= options.min_visibility) || !kp.px.allFinite()) continue;
    if (kp.px.x() < 0 || kp.px.y() < 0 || kp.px.x() > camera.width - 1 ||
        kp.px.y() > camera.height - 1)
      continue;
    c.object.emplace_back(object_points[k].x(), object_points[k].y(), object_points[k].z());
    c.image.emplace_back(kp.px.x(), kp.px.y());
  }
  result.points_used = static_cast<int>(c.object.size());
  if (c.object.size() < 4) return result;  // TooFewPoints
  const Intrinsics in(camera);
  cv::Mat rvec, tvec;
  bool solved = false;
  try {
    if (c.object.size() >= 6) {
      solved = cv::solvePnP(c.object, c.image, in.K, in.D, rvec, tvec, false, cv::SOLVEPNP_EPNP);
      if (solved)
        solved =
            cv::solvePnP(c.object, c.image, in.K, in.D, rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
    } else {
      solved = solveFewPoints(c, in, rvec, tvec);
    }
  } catch (const cv::Exception&) {
    solved = false;
  }
  if (!solved || rvec.empty() || tvec.empty() || !cv::checkRange(rvec) || !cv::checkRange(tvec)) {
    result.status = PnpStatus::SolverFailed;
    return result;
  }
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(tvec, te);
  result.T_camera_object.linear() = Re;
  result.T_camera_object.translation() = te;
  result.reprojection_rms_px = reprojectionRms(c, rvec, tvec, in);
  const Eigen::Vector3d centre = result.T_camera_object * object_points[kCuboidKeypoints - 1];
  if (centre.z() < options.min_depth) {
    result.status = PnpStatus::BehindCamera;
  } else if (result.reprojection_rms_px > options.max_reprojection_px) {
    result.status = PnpStatus::LargeReprojection;
  } else {
    result.status = PnpStatus::Ok;
  }
  return result;
}

}  // namespace sgt::detection
