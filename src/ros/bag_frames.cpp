#include "scene_graph_tracker/ros/bag_frames.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/view.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/CompressedImage.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/make_shared.hpp>

#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/frame_assembler.hpp"

namespace sgt::ros {
namespace {

using Stamp = std::uint64_t;  // nanoseconds
Stamp key(const ::ros::Time& t) { return t.toNSec(); }

// An image message, raw or compressed (decoded: compressed_images.hpp); null for other types.
sensor_msgs::Image::ConstPtr imageOf(const rosbag::MessageInstance& mi) {
  if (auto img = mi.instantiate<sensor_msgs::Image>()) return img;
  if (auto c = mi.instantiate<sensor_msgs::CompressedImage>())
    return boost::make_shared<const sensor_msgs::Image>(decompress(*c));
  return nullptr;
}

std::vector<std::uint8_t> labelsOf(const sensor_msgs::Image& img) {
  if (img.encoding != "mono8" && img.encoding != "8UC1")
    throw ConversionError("label image encoding '" + img.encoding + "' is not mono8");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(img.width) * img.height);
  for (std::size_t y = 0; y < img.height; ++y)
    std::copy_n(img.data.begin() + y * img.step, img.width, out.begin() + y * img.width);
  return out;
}

std::vector<std::string> topicList(std::initializer_list<std::string> topics) { return topics; }

// Pass 2 of a bag: images, scans, hypotheses and labels in time order. A frame is complete when a
// message with a later stamp arrives; the frame assembler builds it, and this adds what only a
// bag has (the colour image for a detector run offline, and ground truth).
class FrameStream {
 public:
  FrameStream(const BagTopics& topics, bool read_rgb, FrameAssembler& assembler,
              const std::function<void(BagFrame&)>& f)
      : topics_(topics), read_rgb_(read_rgb), assembler_(assembler), f_(f) {}

  void readTruth(rosbag::Bag& bag);
  void onMessage(const rosbag::MessageInstance& mi);
  void finish() {
    if (pending_) emit();
  }

 private:
  void store(const std::string& topic, const rosbag::MessageInstance& mi);
  void emit();
  void attachRgb(BagFrame& bf, Stamp k);
  void attachTruth(BagFrame& bf, Stamp k, const sensor_msgs::PointCloud2::ConstPtr& scan);

  const BagTopics& topics_;
  const bool read_rgb_;
  FrameAssembler& assembler_;
  const std::function<void(BagFrame&)>& f_;
  std::map<Stamp, scene_graph_tracker::ObjectPoseArray::ConstPtr> truth_objects_;
  std::map<Stamp, geometry_msgs::PoseStamped::ConstPtr> truth_base_;
  sensor_msgs::CameraInfo::ConstPtr info_, rgb_info_;
  sensor_msgs::Image::ConstPtr pending_;
  std::map<Stamp, sensor_msgs::Image::ConstPtr> rgbs_;  // arrived, not yet used
  std::map<Stamp, std::vector<std::uint8_t>> depth_labels_, lidar_labels_;
  std::vector<std::string> warnings_;
};

void FrameStream::readTruth(rosbag::Bag& bag) {
  for (const rosbag::MessageInstance& mi : rosbag::View(
           bag, rosbag::TopicQuery(topicList({topics_.truth_objects, topics_.truth_base})))) {
    if (auto o = mi.instantiate<scene_graph_tracker::ObjectPoseArray>())
      truth_objects_[key(o->header.stamp)] = o;
    if (auto b = mi.instantiate<geometry_msgs::PoseStamped>())
      truth_base_[key(b->header.stamp)] = b;
  }
}

void FrameStream::onMessage(const rosbag::MessageInstance& mi) {
  const std::string& topic = mi.getTopic();
  if (topic == topics_.depth_info) {
    info_ = mi.instantiate<sensor_msgs::CameraInfo>();
  } else if (topic == topics_.rgb_info) {
    rgb_info_ = mi.instantiate<sensor_msgs::CameraInfo>();
  } else if (topic == topics_.rgb) {
    if (!read_rgb_) return;
    try {
      if (auto img = imageOf(mi)) rgbs_[key(img->header.stamp)] = img;
    } catch (const std::exception& e) {
      warnings_.push_back(topic + " at " + std::to_string(mi.getTime().toSec()) +
                          " skipped: " + e.what());
    }
  } else {
    ::ros::Time stamp = mi.getTime();
    if (auto img = mi.instantiate<sensor_msgs::Image>()) stamp = img->header.stamp;
    if (auto img = mi.instantiate<sensor_msgs::CompressedImage>()) stamp = img->header.stamp;
    if (auto pc = mi.instantiate<sensor_msgs::PointCloud2>()) stamp = pc->header.stamp;
    if (pending_ && stamp > pending_->header.stamp) emit();
    try {
      store(topic, mi);
    } catch (const std::exception& e) {
      warnings_.push_back(topic + " at " + std::to_string(stamp.toSec()) + " skipped: " + e.what());
    }
  }
}

void FrameStream::store(const std::string& topic, const rosbag::MessageInstance& mi) {
  if (topic == topics_.depth) {
    pending_ = imageOf(mi);
  } else if (topic == topics_.lidar) {
    assembler_.addCloud(mi.instantiate<sensor_msgs::PointCloud2>());
  } else if (topic == topics_.hypotheses) {
    assembler_.addHypotheses(mi.instantiate<scene_graph_tracker::PoseHypothesisArray>());
  } else if (topic == topics_.truth_depth_labels) {
    const auto img = mi.instantiate<sensor_msgs::Image>();
    depth_labels_[key(img->header.stamp)] = labelsOf(*img);
  } else if (topic == topics_.truth_lidar_labels) {
    const auto img = mi.instantiate<sensor_msgs::Image>();
    lidar_labels_[key(img->header.stamp)] = labelsOf(*img);
  }
}

void FrameStream::emit() {
  BagFrame bf;
  bf.warnings.swap(warnings_);
  const Stamp k = key(pending_->header.stamp);
  try {
    if (!info_) throw ConversionError("no camera_info before the first depth image");
    AssembledFrame a = assembler_.assemble(*pending_, *info_);
    bf.frame = std::move(a.frame);
    bf.warnings.insert(bf.warnings.end(), a.warnings.begin(), a.warnings.end());
    if (read_rgb_) attachRgb(bf, k);
    attachTruth(bf, k, a.cloud);
  } catch (const std::exception& e) {  // the frame is not usable without its depth image
    bf.warnings.push_back(std::string("depth image at ") +
                          std::to_string(pending_->header.stamp.toSec()) + " skipped: " + e.what());
    warnings_ = std::move(bf.warnings);
    pending_.reset();
    return;
  }
  pending_.reset();
  f_(bf);
}

void FrameStream::attachRgb(BagFrame& bf, Stamp k) {
  if (auto c = rgbs_.find(k); c != rgbs_.end()) {
    try {
      if (!rgb_info_) throw ConversionError("no " + topics_.rgb_info + " before the colour image");
      RgbFrame rgb;
      rgb.camera = toPinhole(*rgb_info_);
      rgb.rgb = rgbFromImage(*c->second, rgb.camera);
      rgb.T_base_camera = assembler_.lookup(topics_.base_frame, c->second->header.frame_id,
                                            c->second->header.stamp);
      bf.rgb = std::move(rgb);
    } catch (const std::exception& e) {
      bf.warnings.push_back("colour image at " + std::to_string(bf.frame.stamp) +
                            " skipped: " + e.what());
    }
  }
  rgbs_.erase(rgbs_.begin(), rgbs_.upper_bound(k));
}

void FrameStream::attachTruth(BagFrame& bf, Stamp k,
                              const sensor_msgs::PointCloud2::ConstPtr& scan) {
  if (auto o = truth_objects_.find(k); o != truth_objects_.end()) {
    GroundTruth gt;
    for (const auto& obj : o->second->objects)
      gt.objects.push_back({obj.id, obj.class_name, toEigen(obj.pose)});
    if (auto b = truth_base_.find(k); b != truth_base_.end())
      gt.T_map_base = toEigen(b->second->pose);
    gt.labels.push_back(depth_labels_.count(k) ? depth_labels_[k] : std::vector<std::uint8_t>{});
    if (scan) {
      const Stamp ks = key(scan->header.stamp);
      gt.labels.push_back(lidar_labels_.count(ks) ? lidar_labels_[ks]
                                                  : std::vector<std::uint8_t>{});
    }
    bf.truth = std::move(gt);
  }
  depth_labels_.erase(depth_labels_.begin(), depth_labels_.upper_bound(k));
}

}  // namespace

BagFrameReader::BagFrameReader(const std::string& path, const BagTopics& topics)
    : path_(path), topics_(topics) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  const ::ros::Time begin = rosbag::View(bag).getBeginTime(), end = rosbag::View(bag).getEndTime();
  tf_ = std::make_unique<tf2::BufferCore>(
      ::ros::Duration(std::max(10.0, (end - begin).toSec() + 10.0)));
  for (const rosbag::MessageInstance& mi :
       rosbag::View(bag, rosbag::TopicQuery(topicList({"/tf", "/tf_static"})))) {
    const auto tf = mi.instantiate<tf2_msgs::TFMessage>();
    if (!tf) continue;
    const bool is_static = mi.getTopic() == "/tf_static";
    for (const auto& t : tf->transforms) tf_->setTransform(t, "bag", is_static);
  }
  depth_count_ = rosbag::View(bag, rosbag::TopicQuery(topicList({topics_.depth}))).size();
  if (depth_count_ == 0) throw std::runtime_error(path + ": no depth images on " + topics_.depth);
  has_truth_ = rosbag::View(bag, rosbag::TopicQuery(topicList({topics_.truth_objects}))).size() > 0;
  for (const rosbag::MessageInstance& mi :
       rosbag::View(bag, rosbag::TopicQuery(topicList({topics_.map_odom_prior}))))
    if (const auto t = mi.instantiate<geometry_msgs::TransformStamped>()) {
      map_odom_prior_ = toEigen(t->transform);
      break;
    }
}

BagFrameReader::~BagFrameReader() = default;

std::optional<Eigen::Isometry3d> BagFrameReader::mapToOdom(double stamp) const {
  if (map_odom_prior_) return map_odom_prior_;
  try {
    return toEigen(tf_->lookupTransform("map", topics_.odom_frame, ::ros::Time(stamp)).transform);
  } catch (const tf2::TransformException&) {
    return std::nullopt;
  }
}

void BagFrameReader::forEach(const std::function<void(BagFrame&)>& f) {
  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  FrameAssemblerOptions options = assembler_options_;
  options.odom_frame = topics_.odom_frame, options.base_frame = topics_.base_frame;
  FrameAssembler assembler(
      options, [this](const std::string& target, const std::string& source, const ::ros::Time& t) {
        return toEigen(tf_->lookupTransform(target, source, t).transform);
      });
  FrameStream stream(topics_, read_rgb_, assembler, f);
  stream.readTruth(bag);
  const auto topics = topicList({topics_.depth, topics_.depth_info, topics_.lidar,
                                 topics_.hypotheses, topics_.truth_depth_labels,
                                 topics_.truth_lidar_labels, topics_.rgb, topics_.rgb_info});
  for (const rosbag::MessageInstance& mi : rosbag::View(bag, rosbag::TopicQuery(topics)))
    stream.onMessage(mi);
  stream.finish();
}

}  // namespace sgt::ros
