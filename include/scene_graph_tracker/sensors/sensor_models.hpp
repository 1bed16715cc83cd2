// Sensor models as plain structs (after Rmagine) and the ray grids they define.
//
// Every model turns into SensorRays: a width x height grid of unit directions in the sensor
// frame, row-major (index = row * width + col), that the ray-casting scene casts from a sensor
// pose. Keeping the grid shape lets the scene cast coherent 4x4 tiles.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace sgt {

// Pinhole camera in the optical frame (REP-103: z forward, x right, y down), parameters as in
// sensor_msgs/CameraInfo's K and D. A pixel's ray goes through the pixel centre (u + 0.5 is not
// used: CameraInfo's cx, cy already refer to pixel centres at integer coordinates). With
// `distortion` (plumb_bob: k1, k2, p1, p2, k3; all 0: none) the rays come from the distorted
// model: an unrectified image's pixel looks along its own, undistorted direction.
struct PinholeModel {
  int width = 640;
  int height = 480;
  double fx = 525.0, fy = 525.0;
  double cx = 319.5, cy = 239.5;
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3
  float range_min = 0.2f;
  float range_max = 10.0f;

  bool distorted() const {
    for (double d : distortion)
      if (d != 0.0) return true;
    return false;
  }
  // Unit ray of pixel (u, v) (undistorted first, when the model is distorted).
  Eigen::Vector3f direction(int u, int v) const;
  // Normalised image coordinates (x/z, y/z) moved by the lens distortion.
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const {
    const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3],
                 k3 = distortion[4];
    const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
            y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
  }
  // Pixel of a point in the optical frame; nullopt behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p) const {
    if (p.z() <= 1e-9) return std::nullopt;
    const Eigen::Vector2d d = distort(Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
    return Eigen::Vector2d(fx * d.x() + cx, fy * d.y() + cy);
  }
  // Primesense / Asus Xtion style camera of the paper: 640x480, ~58 deg horizontal FOV.
  static PinholeModel xtion() { return PinholeModel{}; }
};

// Spinning multi-beam LiDAR in its own frame (x forward, y left, z up). Columns sweep the
// azimuth counter-clockwise from theta_min in steps of theta_inc; rows are rings from
// phi_min (lowest) to phi_max. Defaults: Velodyne VLP-16 in the paper's 1824-column mode.
struct SpinningLidarModel {
  int columns = 1824;
  int rings = 16;
  double theta_min = -M_PI;
  double theta_inc = 2.0 * M_PI / 1824.0;
  double phi_min = -15.0 * M_PI / 180.0;
  double phi_max = 15.0 * M_PI / 180.0;
  float range_min = 0.4f;
  float range_max = 100.0f;

  double phiInc() const { return rings > 1 ? (phi_max - phi_min) / (rings - 1) : 0.0; }
  Eigen::Vector3f direction(int col, int ring) const {
    const double theta = theta_min + col * theta_inc;
    const double phi = phi_min + ring * phiInc();
    return Eigen::Vector3f(static_cast<float>(std::cos(phi) * std::cos(theta)),
                           static_cast<float>(std::cos(phi) * std::sin(theta)),
                           static_cast<float>(std::sin(phi)));
  }
  static SpinningLidarModel vlp16() { return SpinningLidarModel{}; }
};

// Optical frame (z forward, x right, y down) at `eye` looking at `target`, world z up.
Eigen::Isometry3d opticalLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

struct SensorRays {
  int width = 0;
  int height = 0;
  std::vector<Eigen::Vector3f> directions;  // unit, sensor frame, row-major
  // Per-ray origins in the sensor frame; empty means all rays start at the sensor origin.
  std::vector<Eigen::Vector3f> origins;
  float range_min = 0.0f;
  float range_max = std::numeric_limits<float>::infinity();

  std::size_t size() const { return directions.size(); }
  int index(int col, int row) const { return row * width + col; }
};

SensorRays makeRays(const PinholeModel& model);
SensorRays makeRays(const SpinningLidarModel& model);

// An arbitrary ray set (normalises the directions); a single row.
SensorRays makeRays(std::vector<Eigen::Vector3f> directions,
                    std::vector<Eigen::Vector3f> origins = {}, float range_min = 0.0f,
                    float range_max = std::numeric_limits<float>::infinity());

// The rays of the last pinhole model asked for, rebuilt only when its size or intrinsics change
// (a node gets the same camera_info at 30 Hz; rebuilding 300k rays for each frame is wasted work).
class PinholeRayCache {
 public:
  std::shared_ptr<const SensorRays> rays(const PinholeModel& model);

 private:
  std::shared_ptr<const SensorRays> rays_;
  PinholeModel model_;
};

}  // namespace sgt
