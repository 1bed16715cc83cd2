// Reading a recorded (or simulated) bag as pipeline frames, offline and without a roscore.
//
// Frames are assembled as the live tracker assembles them (frame_assembler.hpp), with the
// odometry looked up in the bag's /tf and /tf_static. When the bag carries ground truth (the
// package's simulator writes it) the frame has it too. Topic names are parameters; the defaults
// are what `simulate` writes.
#pragma once

#include <rosbag/bag.h>

#include <functional>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/ros/frame_assembler.hpp"

namespace tf2 {
class BufferCore;
}

namespace sgt::ros {

// The depth and colour topics may be raw (sensor_msgs/Image) or compressed
// (sensor_msgs/CompressedImage, e.g. .../image_raw/compressedDepth and .../compressed:
// compressed_images.hpp).
struct BagTopics {
  std::string depth = "/camera/depth_registered/image_raw";
  std::string depth_info = "/camera/depth_registered/camera_info";
  std::string lidar = "/velodyne_points";
  std::string rgb = "/camera/rgb/image_raw";  // read only when BagFrameReader::setReadRgb(true)
  std::string rgb_info = "/camera/rgb/camera_info";
  std::string hypotheses = "/simulated/pose_hypotheses";
  std::string truth_objects = "/ground_truth/objects";
  std::string truth_base = "/ground_truth/base_pose";
  std::string truth_depth_labels = "/ground_truth/depth_labels";
  std::string truth_lidar_labels = "/ground_truth/velodyne_labels";
  std::string map_odom_prior = "/simulated/map_odom_prior";  // TransformStamped map -> odom
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
};

// Ground-truth labels of measurements as the simulator writes them.
enum class TruthLabel : std::uint8_t { kNone = 0, kStaticMap = 1, kObject = 2, kDistractor = 3 };

struct GroundTruth {
  struct Object {
    std::string id, class_name;
    Eigen::Isometry3d T_map_object;
  };
  std::vector<Object> objects;
  std::optional<Eigen::Isometry3d> T_map_base;
  std::vector<std::vector<std::uint8_t>> labels;  // per measurement set of the frame (may be empty)
};

// The colour image stamped like the frame's depth image (for a detector).
struct RgbFrame {
  cv::Mat rgb;  // 8-bit RGB
  PinholeModel camera;
  Eigen::Isometry3d T_base_camera = Eigen::Isometry3d::Identity();
};

struct BagFrame {
  PipelineFrame frame;
  std::optional<RgbFrame> rgb;  // when reading RGB is on and the bag has the image
  std::optional<GroundTruth> truth;
  std::vector<std::string> warnings;  // what was skipped while building it, and why
};

class BagFrameReader {
 public:
  // Opens the bag and loads its transforms; throws std::runtime_error naming what is missing.
  explicit BagFrameReader(const std::string& path, const BagTopics& topics = {});
  ~BagFrameReader();

  std::size_t frameCount() const { return depth_count_; }
  bool hasGroundTruth() const { return has_truth_; }
  // Also attach each frame's colour image (off by default: it costs decoding time).
  void setReadRgb(bool on) { read_rgb_ = on; }
  // How frames are assembled (the LiDAR model, the hypotheses' time window); the frames named in
  // BagTopics win over the options' own.
  void setAssemblerOptions(const FrameAssemblerOptions& o) { assembler_options_ = o; }
  // The bag's map -> odom prior: the simulator's (map_odom_prior topic) or, in a bag recorded
  // with a localizer running, its map -> odom on /tf at `stamp`; nullopt when it has neither.
  std::optional<Eigen::Isometry3d> mapToOdom(double stamp) const;
  // Calls `f` for every frame in stamp order.
  void forEach(const std::function<void(BagFrame&)>& f);

 private:
  std::string path_;
  BagTopics topics_;
  std::unique_ptr<tf2::BufferCore> tf_;
  std::size_t depth_count_ = 0;
  bool has_truth_ = false;
  bool read_rgb_ = false;
  FrameAssemblerOptions assembler_options_;
  std::optional<Eigen::Isometry3d> map_odom_prior_;
};

}  // namespace sgt::ros
