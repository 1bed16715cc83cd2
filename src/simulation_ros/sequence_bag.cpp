#include "scene_graph_tracker/simulation/sequence_bag.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "bag_messages.hpp"
#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/scenario_bag.hpp"

namespace sgt::ros {
namespace {

namespace enc = sensor_msgs::image_encodings;

std::vector<std::uint8_t> bytesOf(const cv::Mat& m) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  return std::vector<std::uint8_t>(c.data, c.data + c.total() * c.elemSize());
}

// Depth in metres (NaN = no return) back to 16-bit millimetres (0 = no return).
cv::Mat millimetres(const std::vector<float>& depth, const PinholeModel& cam) {
  cv::Mat mm(cam.height, cam.width, CV_16UC1);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const float d = depth[static_cast<std::size_t>(v) * cam.width + u];
      mm.at<std::uint16_t>(v, u) =
          std::isfinite(d)
              ? static_cast<std::uint16_t>(std::lround(std::clamp(d * 1000.0f, 0.0f, 65535.0f)))
              : 0;
    }
  return mm;
}

std::vector<std::string> objectsOf(const RgbdSequence& s, const SequenceBagOptions& o) {
  if (o.objects.empty()) return s.objectNames();
  for (const std::string& name : o.objects)
    if (!s.T_map_object.count(name))
      throw SequenceError(s.dir + ": the sequence has no object '" + name + "'");
  return o.objects;
}

class SequenceWriter {
 public:
  SequenceWriter(const RgbdSequence& s, rosbag::Bag& bag, const SequenceBagOptions& o)
      : s_(s), bag_(bag), o_(o), objects_(objectsOf(s, o)), rng_(o.seed) {}
  void write(std::size_t k, SequenceBagSummary& summary);

 private:
  void writeImages(const RgbdSequence::Frame& f, const std_msgs::Header& h);
  void writeTruth(const RgbdSequence::Frame& f, const ::ros::Time& stamp);
  std::size_t writeHypotheses(const RgbdSequence::Frame& f, const std_msgs::Header& h);

  const RgbdSequence& s_;
  rosbag::Bag& bag_;
  const SequenceBagOptions& o_;
  const std::vector<std::string> objects_;
  std::mt19937 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

void SequenceWriter::write(std::size_t k, SequenceBagSummary& summary) {
  const RgbdSequence::Frame& f = s_.frames[k];
  const ::ros::Time stamp(o_.start_time + static_cast<double>(k) / o_.rate_hz);
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(transform(stamp, frames::kMap, o_.camera_frame.c_str(), f.T_map_camera));
  bag_.write(topics::kTf, stamp, tf);
  const std_msgs::Header h = header(stamp, o_.camera_frame.c_str());
  writeImages(f, h);
  writeTruth(f, stamp);
  summary.hypotheses += writeHypotheses(f, h);
  ++summary.frames;
}

void SequenceWriter::writeImages(const RgbdSequence::Frame& f, const std_msgs::Header& h) {
  const PinholeModel& cam = s_.camera;
  sensor_msgs::CameraInfo info = toCameraInfo(cam);
  info.header = h;
  const cv::Mat rgb = loadSequenceRgb(s_, f);
  const cv::Mat depth_mm = millimetres(loadSequenceDepth(s_, f), cam);
  if (o_.compressed) {
    bag_.write(std::string(topics::kRgb) + "/compressed", h.stamp, compressRgbJpeg(h, rgb));
    bag_.write(std::string(topics::kDepth) + "/compressedDepth", h.stamp,
               compressDepthMillimetres(h, depth_mm));
  } else {
    bag_.write(topics::kRgb, h.stamp, image(h, cam.width, cam.height, enc::RGB8, 3, bytesOf(rgb)));
    sensor_msgs::Image depth = image(h, cam.width, cam.height, enc::TYPE_16UC1, 1, {});
    depth.step = 2 * cam.width;
    depth.data = bytesOf(depth_mm);
    bag_.write(topics::kDepth, h.stamp, depth);
  }
  bag_.write(topics::kRgbInfo, h.stamp, info);
  bag_.write(topics::kDepthInfo, h.stamp, info);
}

void SequenceWriter::writeTruth(const RgbdSequence::Frame& f, const ::ros::Time& stamp) {
  scene_graph_tracker::ObjectPoseArray truth;
  truth.header = header(stamp, frames::kMap);
  for (const std::string& name : objects_) {
    const auto given = f.T_camera_object.find(name);
    scene_graph_tracker::ObjectPose o;
    o.id = o.class_name = name;
    o.pose = toPose(given != f.T_camera_object.end() ? f.T_map_camera * given->second
                                                     : s_.T_map_object.at(name));
    truth.objects.push_back(std::move(o));
  }
  bag_.write(topics::kGtObjects, stamp, truth);
  geometry_msgs::PoseStamped base;
  base.header = truth.header;
  base.pose = toPose(f.T_map_camera);
  bag_.write(topics::kGtBasePose, stamp, base);
}

std::size_t SequenceWriter::writeHypotheses(const RgbdSequence::Frame& f,
                                            const std_msgs::Header& h) {
  scene_graph_tracker::PoseHypothesisArray out;
  out.header = h;
  for (const std::string& name : objects_) {
    const auto given = f.T_camera_object.find(name);
    const Eigen::Isometry3d T = given != f.T_camera_object.end()
                                    ? given->second
                                    : f.T_map_camera.inverse() * s_.T_map_object.at(name);
    const Eigen::Isometry3d noisy =
        disturbPose(T, o_.sigma_t, o_.sigma_r_deg * M_PI / 180.0, rng_, gauss_);
    if (uniform_(rng_) < o_.miss_probability) continue;
    scene_graph_tracker::PoseHypothesis p;
    p.class_name = name;
    p.pose = toPose(noisy);
    p.score = 0.9f;
    out.hypotheses.push_back(std::move(p));
  }
  bag_.write(topics::kHypotheses, h.stamp, out);
  return out.hypotheses.size();
}

}  // namespace

SequenceBagSummary writeSequenceBag(const RgbdSequence& sequence, const std::string& path,
                                    const SequenceBagOptions& options,
                                    const std::function<void(std::size_t, std::size_t)>& progress) {
  if (!(options.rate_hz > 0.0)) throw SequenceError("the frame rate must be > 0");
  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  SequenceWriter writer(sequence, bag, options);
  SequenceBagSummary summary;
  for (std::size_t k = 0; k < sequence.frames.size(); ++k) {
    writer.write(k, summary);
    if (progress) progress(k + 1, sequence.frames.size());
  }
  bag.close();
  return summary;
}

}  // namespace sgt::ros
