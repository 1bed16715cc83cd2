#include "scene_graph_tracker/evaluation/rgbd_sequence.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace sgt {
namespace {

using nlohmann::json;

json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SequenceError(path + ": cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw SequenceError(path + ": " + e.what());
  }
}

double number(const json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_number())
    throw SequenceError(where + ": '" + key + "' is missing or not a number");
  return j[key].get<double>();
}

// A row-major 4x4 rigid transform; throws unless its rotation is orthonormal.
Eigen::Isometry3d pose(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 4) throw SequenceError(where + ": expected a 4x4 list");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    if (!j[r].is_array() || j[r].size() != 4) throw SequenceError(where + ": expected a 4x4 list");
    for (int c = 0; c < 4; ++c) {
      if (!j[r][c].is_number()) throw SequenceError(where + ": not a number");
      m(r, c) = j[r][c].get<double>();
    }
  }
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (!m.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-4 ||
      R.determinant() < 0.0)
    throw SequenceError(where + ": not a rigid transform");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

PinholeModel cameraFrom(const json& j, const std::string& where, double& depth_unit_m) {
  PinholeModel cam;
  cam.width = static_cast<int>(number(j, "width", where));
  cam.height = static_cast<int>(number(j, "height", where));
  cam.fx = number(j, "fx", where), cam.fy = number(j, "fy", where);
  cam.cx = number(j, "cx", where), cam.cy = number(j, "cy", where);
  depth_unit_m = j.contains("depth_unit_m") ? number(j, "depth_unit_m", where) : 0.001;
  if (j.contains("distortion") && j["distortion"] != "none")
    throw SequenceError(where + ": only undistorted images are supported (distortion: none)");
  if (cam.width <= 0 || cam.height <= 0 || cam.fx <= 0 || cam.fy <= 0 || depth_unit_m <= 0)
    throw SequenceError(where + ": the image size, focal lengths and depth unit must be > 0");
  return cam;
}

std::string imageName(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", index);
  return name;
}

RgbdSequence::Frame frameFrom(const json& j, const std::string& dir, const std::string& where) {
  RgbdSequence::Frame f;
  f.index = static_cast<int>(number(j, "frame", where));
  f.rgb_path = dir + "/rgb/" + imageName(f.index);
  f.depth_path = dir + "/depth/" + imageName(f.index);
  for (const std::string& p : {f.rgb_path, f.depth_path})
    if (!std::filesystem::exists(p)) throw SequenceError(where + ": " + p + " does not exist");
  if (!j.contains("T_map_camera")) throw SequenceError(where + ": no T_map_camera");
  f.T_map_camera = pose(j["T_map_camera"], where + ".T_map_camera");
  if (j.contains("objects"))
    for (const auto& [name, T] : j["objects"].items())
      f.T_camera_object[name] = pose(T, where + ".objects." + name);
  return f;
}

}  // namespace

std::vector<std::string> RgbdSequence::objectNames() const {
  std::vector<std::string> names;
  for (const auto& [name, T] : T_map_object) names.push_back(name);
  return names;
}

std::string RgbdSequence::meshPath(const std::string& object) const {
  return dir + "/models/" + object + ".ply";
}

RgbdSequence loadRgbdSequence(const std::string& dir) {
  RgbdSequence s;
  s.dir = dir;
  const std::string camera_file = dir + "/camera.json", poses_file = dir + "/poses.json";
  s.camera = cameraFrom(readJson(camera_file), camera_file, s.depth_unit_m);
  const json poses = readJson(poses_file);
  if (!poses.contains("frames") || !poses["frames"].is_array() || poses["frames"].empty())
    throw SequenceError(poses_file + ": 'frames' is missing or empty");
  for (std::size_t k = 0; k < poses["frames"].size(); ++k)
    s.frames.push_back(
        frameFrom(poses["frames"][k], dir, poses_file + ": frames[" + std::to_string(k) + "]"));
  if (poses.contains("T_map_object"))
    for (const auto& [name, T] : poses["T_map_object"].items())
      s.T_map_object[name] = pose(T, poses_file + ": T_map_object." + name);
  for (const RgbdSequence::Frame& f : s.frames)  // objects given per frame only
    for (const auto& [name, T] : f.T_camera_object)
      if (!s.T_map_object.count(name)) s.T_map_object[name] = f.T_map_camera * T;
  for (const std::string& name : s.objectNames())
    if (!std::filesystem::exists(s.meshPath(name)))
      throw SequenceError(dir + ": object " + name + " has no mesh " + s.meshPath(name));
  return s;
}

cv::Mat loadSequenceRgb(const RgbdSequence& s, const RgbdSequence::Frame& f) {
  const cv::Mat bgr = cv::imread(f.rgb_path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw SequenceError(f.rgb_path + ": not an image");
  if (bgr.cols != s.camera.width || bgr.rows != s.camera.height)
    throw SequenceError(f.rgb_path + ": its size differs from camera.json's");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

std::vector<float> loadSequenceDepth(const RgbdSequence& s, const RgbdSequence::Frame& f) {
  const cv::Mat d = cv::imread(f.depth_path, cv::IMREAD_ANYDEPTH);
  if (d.empty() || d.type() != CV_16UC1)
    throw SequenceError(f.depth_path + ": not a 16-bit single-channel image");
  if (d.cols != s.camera.width || d.rows != s.camera.height)
    throw SequenceError(f.depth_path + ": its size differs from camera.json's");
  std::vector<float> metres(d.total());
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const std::uint16_t raw = d.at<std::uint16_t>(v, u);
      metres[static_cast<std::size_t>(v) * d.cols + u] =
          raw == 0 ? NAN : static_cast<float>(raw * s.depth_unit_m);
    }
  return metres;
}

}  // namespace sgt
