// Writes a recorded RGB-D sequence (evaluation/rgbd_sequence.hpp) into a bag that the evaluator
// and the tracker read like a robot's recording with an external localization:
//
//   /tf         (per frame)  map -> camera_color_optical_frame: the sequence's T_map_camera (the
//                            camera is the robot: evaluate --odom-frame map --base-frame
//                            camera_color_optical_frame --localization external)
//   /camera/rgb/image_raw (rgb8), /camera/depth_registered/image_raw (16UC1 mm, 0 = no return),
//   both camera_info (plumb_bob, no distortion); with `compressed`, .../image_raw/compressed (JPEG)
//   and /camera/depth_registered/image_raw/compressedDepth (PNG) instead of the raw images
//   /ground_truth/objects    (ObjectPoseArray, frame map): the given poses, id = class = name
//   /ground_truth/base_pose  (PoseStamped, frame map): T_map_camera
//   /simulated/pose_hypotheses (frame camera): the given poses disturbed by the simulated
//                            detector's noise (simulation/noise.hpp), minus seeded misses
// Frame k is stamped start_time + k / rate_hz (the sequence's own timestamps are not used).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene_graph_tracker/evaluation/rgbd_sequence.hpp"

namespace sgt::ros {

struct SequenceBagOptions {
  double rate_hz = 15.0;
  double start_time = 1700000000.0;
  std::vector<std::string> objects;  // empty: all of the sequence's
  double sigma_t = 0.01;             // m per axis, as the simulator's default detections
  double sigma_r_deg = 2.0;          // per axis of the rotation vector
  double miss_probability = 0.0;
  std::uint32_t seed = 1;
  bool compressed = false;
  std::string camera_frame = "camera_color_optical_frame";
};

struct SequenceBagSummary {
  std::size_t frames = 0, hypotheses = 0;
};

// Throws SequenceError on a bad sequence or an unknown object name, rosbag's exceptions on I/O.
SequenceBagSummary writeSequenceBag(
    const RgbdSequence& sequence, const std::string& path, const SequenceBagOptions& options = {},
    const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace sgt::ros
