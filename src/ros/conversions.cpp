#include "scene_graph_tracker/ros/conversions.hpp"

#include <cv_bridge/cv_bridge.h>
#include <scene_graph_tracker/TrackedObject.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

namespace sgt::ros {

Eigen::Isometry3d toEigen(const geometry_msgs::Pose& p) {
  Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  // Every component finite (an infinite one has an infinite norm, and normalizing by it gave a
  // NaN rotation); the norm without overflow, so that huge finite components still normalize.
  const double norm = q.coeffs().allFinite() ? q.coeffs().stableNorm() : 0.0;
  if (!(norm > 1e-9)) throw ConversionError("pose with a zero or non-finite quaternion");
  if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z))
    throw ConversionError("pose with a non-finite position");
  q.coeffs() /= norm;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t) {
  geometry_msgs::Pose p;
  p.position.x = t.translation.x, p.position.y = t.translation.y, p.position.z = t.translation.z;
  p.orientation = t.rotation;
  return toEigen(p);
}

geometry_msgs::Pose toPose(const Eigen::Isometry3d& T) {
  geometry_msgs::Pose p;
  const Eigen::Quaterniond q(T.linear());
  p.position.x = T.translation().x(), p.position.y = T.translation().y(),
  p.position.z = T.translation().z();
  p.orientation.w = q.w(), p.orientation.x = q.x(), p.orientation.y = q.y(),
  p.orientation.z = q.z();
  return p;
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) {
  const geometry_msgs::Pose p = toPose(T);
  geometry_msgs::Transform t;
  t.translation.x = p.position.x, t.translation.y = p.position.y, t.translation.z = p.position.z;
  t.rotation = p.orientation;
  return t;
}

PinholeModel toPinhole(const sensor_msgs::CameraInfo& info, float range_min, float range_max) {
  if (info.width == 0 || info.height == 0)
    throw ConversionError("camera_info has a zero image size");
  // Larger than any camera: rays for it would take gigabytes before the image is even looked at.
  constexpr std::uint64_t kMaxSide = 16384, kMaxPixels = 64ull << 20;
  if (info.width > kMaxSide || info.height > kMaxSide ||
      std::uint64_t(info.width) * info.height > kMaxPixels)
    throw ConversionError("camera_info image size " + std::to_string(info.width) + "x" +
                          std::to_string(info.height) + " is beyond any camera");
  if (!std::isfinite(info.K[0]) || !std::isfinite(info.K[4]) || !std::isfinite(info.K[2]) ||
      !std::isfinite(info.K[5]))
    throw ConversionError("camera_info K is not finite");
  if (!(info.K[0] > 0.0) || !(info.K[4] > 0.0))
    throw ConversionError("camera_info has no focal length (K[0] = " + std::to_string(info.K[0]) +
                          ", K[4] = " + std::to_string(info.K[4]) + ")");
  PinholeModel cam;
  cam.width = static_cast<int>(info.width), cam.height = static_cast<int>(info.height);
  cam.fx = info.K[0], cam.fy = info.K[4], cam.cx = info.K[2], cam.cy = info.K[5];
  cam.range_min = range_min, cam.range_max = range_max;
  const bool none = std::all_of(info.D.begin(), info.D.end(), [](double d) { return d == 0.0; });
  if (none) return cam;
  if (info.distortion_model != "plumb_bob" || info.D.size() != 5)
    throw ConversionError("camera_info distortion '" + info.distortion_model + "' with " +
                          std::to_string(info.D.size()) +
                          " coefficients is not supported (plumb_bob with 5 is; or rectify the "
                          "images, e.g. with image_proc)");
  for (std::size_t k = 0; k < 5; ++k) {
    if (!std::isfinite(info.D[k])) throw ConversionError("camera_info D is not finite");
    cam.distortion[k] = info.D[k];
  }
  return cam;
}

sensor_msgs::CameraInfo toCameraInfo(const PinholeModel& cam) {
  sensor_msgs::CameraInfo info;
  info.width = cam.width, info.height = cam.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(cam.distortion.begin(), cam.distortion.end());
  info.K = {cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {cam.fx, 0, cam.cx, 0, 0, cam.fy, cam.cy, 0, 0, 0, 1, 0};
  return info;
}

std::vector<float> depthFromImage(const sensor_msgs::Image& img, const PinholeModel& cam) {
  namespace enc = sensor_msgs::image_encodings;
  if (static_cast<int>(img.width) != cam.width || static_cast<int>(img.height) != cam.height)
    throw ConversionError("depth image is " + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " but camera_info says " +
                          std::to_string(cam.width) + "x" + std::to_string(cam.height));
  const bool f32 = img.encoding == enc::TYPE_32FC1,
             u16 = img.encoding == enc::TYPE_16UC1 || img.encoding == enc::MONO16;
  if (!f32 && !u16)
    throw ConversionError("depth image encoding '" + img.encoding +
                          "' is not supported (use 32FC1 m or 16UC1 mm)");
  const std::size_t bpp = f32 ? 4 : 2, w = img.width, h = img.height;
  if (img.step < w * bpp || img.data.size() < img.step * h)
    throw ConversionError("depth image data is too short: step " + std::to_string(img.step) + ", " +
                          std::to_string(img.data.size()) + " bytes for " + std::to_string(w) +
                          "x" + std::to_string(h));
  if (img.is_bigendian) throw ConversionError("big-endian depth images are not supported");
  std::vector<float> depth(w * h);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* row = img.data.data() + y * img.step;
    for (std::size_t x = 0; x < w; ++x) {
      float d;
      if (f32) {
        std::memcpy(&d, row + 4 * x, 4);
      } else {
        std::uint16_t mm;
        std::memcpy(&mm, row + 2 * x, 2);
        d = mm * 0.001f;
      }
      depth[y * w + x] = std::isfinite(d) && d > 0.0f ? d : std::numeric_limits<float>::quiet_NaN();
    }
  }
  return depth;
}

sensor_msgs::Image depthToImage(const std::vector<float>& depth_m, int width, int height) {
  sensor_msgs::Image img;
  img.width = width, img.height = height;
  img.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  img.is_bigendian = 0;
  img.step = 4 * width;
  img.data.resize(depth_m.size() * 4);
  std::memcpy(img.data.data(), depth_m.data(), img.data.size());
  return img;
}

namespace {

// Where x, y and z are in each point, checked against the message's own sizes: a malformed cloud
// is rejected with a reason, never read out of bounds.
struct CloudLayout {
  std::uint32_t offset[3] = {0, 0, 0};
  bool float64 = false;  // x, y, z are FLOAT64 (else FLOAT32)
  std::size_t points = 0;
};

CloudLayout cloudLayout(const sensor_msgs::PointCloud2& cloud) {
  CloudLayout l;
  int type[3] = {0, 0, 0};
  for (const auto& f : cloud.fields)
    for (int k = 0; k < 3; ++k)
      if (f.name == std::string(1, "xyz"[k])) {
        if (f.datatype != sensor_msgs::PointField::FLOAT32 &&
            f.datatype != sensor_msgs::PointField::FLOAT64)
          throw ConversionError("point cloud field '" + f.name +
                                "' is neither float32 nor float64");
        const unsigned size = f.datatype == sensor_msgs::PointField::FLOAT64 ? 8 : 4;
        if (std::uint64_t(f.offset) + size > cloud.point_step)
          throw ConversionError("point cloud field '" + f.name + "' lies beyond point_step");
        type[k] = f.datatype, l.offset[k] = f.offset;
      }
  if (!type[0] || !type[1] || !type[2]) throw ConversionError("point cloud has no x, y, z fields");
  if (type[0] != type[1] || type[1] != type[2])
    throw ConversionError("point cloud fields x, y, z are of different types");
  l.float64 = type[0] == sensor_msgs::PointField::FLOAT64;
  const std::uint64_t row = std::uint64_t(cloud.width) * cloud.point_step;
  if (cloud.height > 0 && cloud.width > 0 && cloud.row_step < row)
    throw ConversionError("point cloud row_step is shorter than width x point_step");
  const std::uint64_t needed =
      cloud.height == 0 ? 0 : std::uint64_t(cloud.height - 1) * cloud.row_step + row;
  if (cloud.data.size() < needed)
    throw ConversionError("point cloud data is shorter than its rows");
  l.points = std::size_t(cloud.width) * cloud.height;
  return l;
}

// A value in the message's byte order, as the host's.
template <typename T>
T readValue(const std::uint8_t* p, bool swap) {
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof b);
  if (swap) std::reverse(b, b + sizeof b);
  T v;
  std::memcpy(&v, b, sizeof v);
  return v;
}

// Point i of the cloud in its frame.
Eigen::Vector3f cloudPoint(const sensor_msgs::PointCloud2& cloud, const CloudLayout& l,
                           std::size_t i, bool swap) {
  const std::uint8_t* p = cloud.data.data() + (i / cloud.width) * std::size_t(cloud.row_step) +
                          (i % cloud.width) * std::size_t(cloud.point_step);
  Eigen::Vector3f v;
  for (int k = 0; k < 3; ++k)
    v[k] = l.float64 ? static_cast<float>(readValue<double>(p + l.offset[k], swap))
                     : readValue<float>(p + l.offset[k], swap);
  return v;
}

// A point's distance from the sensor, always by this expression: Eigen's norm() can differ in the
// last bit, and the tracker's results follow such bits (doc/experiments.md, section 20).
float pointRange(const Eigen::Vector3f& p) {
  return std::sqrt(p.x() * p.x() + p.y() * p.y() + p.z() * p.z());
}

bool swapped(const sensor_msgs::PointCloud2& cloud) {
  return cloud.is_bigendian != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
}

}  // namespace

bool matchesGrid(const sensor_msgs::PointCloud2& cloud, const SpinningLidarModel& grid) {
  return cloud.height == static_cast<std::uint32_t>(grid.rings) &&
         cloud.width == static_cast<std::uint32_t>(grid.columns);
}

RangeMeasurements measurementsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                        const SpinningLidarModel& grid,
                                        std::shared_ptr<const SensorRays> grid_rays,
                                        const Eigen::Isometry3d& T_world_sensor) {
  const CloudLayout l = cloudLayout(cloud);
  const bool swap = swapped(cloud);
  const std::string& sensor = cloud.header.frame_id;
  if (matchesGrid(cloud, grid)) {
    std::vector<float> ranges(l.points, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < l.points; ++i) {
      const Eigen::Vector3f p = cloudPoint(cloud, l, i, swap);
      const float r = pointRange(p);
      if (std::isfinite(r) && r > 0.0f) ranges[i] = r;
    }
    return fromRanges(grid, std::move(grid_rays), std::move(ranges), T_world_sensor, sensor);
  }
  std::vector<Eigen::Vector3f> directions;
  std::vector<float> ranges;
  directions.reserve(l.points), ranges.reserve(l.points);
  for (std::size_t i = 0; i < l.points; ++i) {
    const Eigen::Vector3f p = cloudPoint(cloud, l, i, swap);
    const float r = pointRange(p);
    if (!std::isfinite(r) || !(r > 0.0f)) continue;  // no return: no ray
    directions.push_back(p / r), ranges.push_back(r);
  }
  auto rays = std::make_shared<SensorRays>(
      makeRays(std::move(directions), {}, grid.range_min, grid.range_max));
  return fromRanges(PointRays{}, std::move(rays), std::move(ranges), T_world_sensor, sensor);
}

RangeMeasurements measurementsFromScan(const sensor_msgs::LaserScan& scan,
                                       const Eigen::Isometry3d& T_world_sensor) {
  if (!std::isfinite(scan.angle_min) || !std::isfinite(scan.angle_increment) ||
      scan.angle_increment == 0.0f)
    throw ConversionError("laser scan with a non-finite or zero angle step");
  if (!(scan.range_min >= 0.0f) || !(scan.range_min < scan.range_max))
    throw ConversionError("laser scan whose range_min is not below range_max");
  constexpr std::size_t kMaxBeams = 1 << 20;
  if (scan.ranges.size() > kMaxBeams) throw ConversionError("laser scan with over 2^20 beams");
  std::vector<Eigen::Vector3f> directions(scan.ranges.size());
  std::vector<float> ranges(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = double(scan.angle_min) + double(i) * scan.angle_increment;
    directions[i] =
        Eigen::Vector3f(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f);
    const float r = scan.ranges[i];  // beyond [range_min, range_max]: no return
    ranges[i] = std::isfinite(r) && r >= scan.range_min && r <= scan.range_max
                    ? r
                    : std::numeric_limits<float>::quiet_NaN();
  }
  auto rays = std::make_shared<SensorRays>(
      makeRays(std::move(directions), {}, scan.range_min, scan.range_max));
  return fromRanges(PointRays{}, std::move(rays), std::move(ranges), T_world_sensor,
                    scan.header.frame_id);
}

sensor_msgs::PointCloud2 cloudFromRanges(const std::vector<float>& ranges, const SensorRays& rays,
                                         const std::vector<float>& intensity) {
  sensor_msgs::PointCloud2 cloud;
  cloud.height = rays.height, cloud.width = rays.width;
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2Fields(
      5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "intensity", 1, sensor_msgs::PointField::FLOAT32, "ring", 1,
      sensor_msgs::PointField::UINT16);
  cloud.is_dense = false;
  // Points are 18 bytes apart, so most of their floats are not 4-byte aligned: copy the bytes
  // (PointCloud2Iterator's float references would be misaligned, undefined behaviour).
  const auto put = [&](std::uint8_t* point, int field, const auto& value) {
    std::memcpy(point + cloud.fields[field].offset, &value, sizeof value);
  };
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const float r = ranges[i];
    const bool ok = std::isfinite(r) && r > 0.0f;
    const Eigen::Vector3f p =
        ok ? Eigen::Vector3f(rays.directions[i] * r)
           : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
    std::uint8_t* point = cloud.data.data() + i * cloud.point_step;
    put(point, 0, p.x()), put(point, 1, p.y()), put(point, 2, p.z());
    put(point, 3, i < intensity.size() ? intensity[i] : 0.0f);
    put(point, 4, static_cast<std::uint16_t>(i / rays.width));
  }
  return cloud;
}

cv::Mat rgbFromImage(const sensor_msgs::Image& img, const PinholeModel& cam) {
  namespace enc = sensor_msgs::image_encodings;
  if (img.width == 0 || img.height == 0 || img.data.empty())
    throw ConversionError("colour image is empty");
  if (static_cast<int>(img.width) != cam.width || static_cast<int>(img.height) != cam.height)
    throw ConversionError("colour image is " + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " but its camera_info says " +
                          std::to_string(cam.width) + "x" + std::to_string(cam.height));
  if (img.encoding != enc::RGB8 && img.encoding != enc::BGR8 && img.encoding != enc::RGBA8 &&
      img.encoding != enc::BGRA8 && img.encoding != enc::MONO8)
    throw ConversionError("colour image encoding '" + img.encoding +
                          "' is not supported (use rgb8, bgr8, rgba8, bgra8 or mono8)");
  // Checked here in 64 bits: cv_bridge compares height x step in 32 bits, which wraps around
  // for a large step and lets it read rows beyond the data.
  const std::uint64_t bpp = img.encoding == enc::MONO8                               ? 1
                            : img.encoding == enc::RGB8 || img.encoding == enc::BGR8 ? 3
                                                                                     : 4;
  if (img.step < bpp * img.width || img.data.size() != std::uint64_t(img.step) * img.height)
    throw ConversionError("colour image data does not fit its size: step " +
                          std::to_string(img.step) + ", " + std::to_string(img.data.size()) +
                          " bytes for " + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " " + img.encoding);
  try {
    return cv_bridge::toCvCopy(img, enc::RGB8)->image;
  } catch (const cv_bridge::Exception& e) {
    throw ConversionError(std::string("colour image: ") + e.what());
  }
}

std::uint8_t toStateCode(TrackState s) {
  return s == TrackState::kTentative   ? scene_graph_tracker::TrackedObject::TENTATIVE
         : s == TrackState::kConfirmed ? scene_graph_tracker::TrackedObject::CONFIRMED
                                       : scene_graph_tracker::TrackedObject::LOST;
}

TrackState fromStateCode(std::uint8_t code) {
  return code == scene_graph_tracker::TrackedObject::CONFIRMED ? TrackState::kConfirmed
         : code == scene_graph_tracker::TrackedObject::LOST    ? TrackState::kLost
                                                               : TrackState::kTentative;
}

}  // namespace sgt::ros
