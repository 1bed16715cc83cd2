// An RGB-D sequence folder (a recording of a real camera, e.g. ../shared/data/real/visp_rbt):
//   rgb/NNNNNN.png     8-bit colour, registered with the depth
//   depth/NNNNNN.png   16-bit depth in units of camera.json's depth_unit_m (0 = no return)
//   camera.json        width, height, fx, fy, cx, cy, depth_unit_m, distortion ("none")
//   poses.json         frames[k] = {frame, T_map_camera, objects{name: T_camera_object}},
//                      T_map_object{name: pose}; poses are row-major 4x4 lists in metres
//   models/NAME.ply    the objects' meshes (metres, origin as in poses.json)
// loadRgbdSequence() checks the layout and every pose and throws SequenceError naming the file
// and what is wrong. Images are read when asked for.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt {

struct SequenceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RgbdSequence {
  struct Frame {
    int index = 0;  // the number in the image file names
    std::string rgb_path, depth_path;
    Eigen::Isometry3d T_map_camera = Eigen::Isometry3d::Identity();
    std::map<std::string, Eigen::Isometry3d> T_camera_object;  // the given poses in this frame
  };
  std::string dir;
  PinholeModel camera;
  double depth_unit_m = 0.001;
  std::vector<Frame> frames;
  std::map<std::string, Eigen::Isometry3d> T_map_object;  // names = the objects of the sequence

  std::vector<std::string> objectNames() const;
  std::string meshPath(const std::string& object) const;  // dir/models/NAME.ply
};

RgbdSequence loadRgbdSequence(const std::string& dir);
// The frame's colour image as RGB (8-bit, 3 channels); its depth in metres, NaN = no return.
// Both throw SequenceError when the file is missing or does not match the camera.
cv::Mat loadSequenceRgb(const RgbdSequence& s, const RgbdSequence::Frame& f);
std::vector<float> loadSequenceDepth(const RgbdSequence& s, const RgbdSequence::Frame& f);

}  // namespace sgt
