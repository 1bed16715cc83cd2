#include "scene_graph_tracker/ros/bag_frames.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/view.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

using Stamp = std::uint64_t;  // nanoseconds
Stamp key(const ::ros::Time& t) { return t.toNSec(); }

std::vector<std::uint8_t> labelsOf(const sensor_msgs::Image& img) {
  if (img.encoding != "mono8" && img.encoding != "8UC1")
    throw ConversionError("label image encoding '" + img.encoding + "' is not mono8");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(img.width) * img.height);
  for (std::size_t y = 0; y < img.height; ++y)
    std::copy_n(img.data.begin() + y * img.step, img.width, out.begin() + y * img.width);
  return out;
}

struct Scan {
  sensor_msgs::PointCloud2::ConstPtr cloud;
};

}  // namespace

BagFrameReader::BagFrameReader(const std::string& path, const BagTopics& topics) : path_(path), topics_(topics) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  const ::ros::Time begin = rosbag::View(bag).getBeginTime(), end = rosbag::View(bag).getEndTime();
  tf_ = std::make_unique<tf2::BufferCore>(::ros::Duration(std::max(10.0, (end - begin).toSec() + 10.0)));
  for (const rosbag::MessageInstance& mi : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}))) {
    const auto tf = mi.instantiate<tf2_msgs::TFMessage>();
    if (!tf) continue;
    const bool is_static = mi.getTopic() == "/tf_static";
    for (const auto& t : tf->transforms) tf_->setTransform(t, "bag", is_static);
  }
  depth_count_ = rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{topics_.depth})).size();
  if (depth_count_ == 0) throw std::runtime_error(path + ": no depth images on " + topics_.depth);
  has_truth_ = rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{topics_.truth_objects})).size() > 0;
  for (const rosbag::MessageInstance& mi : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{topics_.map_odom_prior})))
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
  // Pass 1: the small messages, by stamp.
  std::map<Stamp, scene_graph_tracker::PoseHypothesisArray::ConstPtr> hypotheses;
  std::map<Stamp, scene_graph_tracker::ObjectPoseArray::ConstPtr> truth_objects;
  std::map<Stamp, geometry_msgs::PoseStamped::ConstPtr> truth_base;
  for (const rosbag::MessageInstance& mi :
       rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{topics_.hypotheses, topics_.truth_objects, topics_.truth_base}))) {
    if (auto h = mi.instantiate<scene_graph_tracker::PoseHypothesisArray>()) hypotheses[key(h->header.stamp)] = h;
    if (auto o = mi.instantiate<scene_graph_tracker::ObjectPoseArray>()) truth_objects[key(o->header.stamp)] = o;
    if (auto b = mi.instantiate<geometry_msgs::PoseStamped>()) truth_base[key(b->header.stamp)] = b;
  }
  // Pass 2: images and scans in time order; a frame is complete when a later message arrives.
  sensor_msgs::CameraInfo::ConstPtr info, rgb_info;
  sensor_msgs::Image::ConstPtr pending;
  std::map<Stamp, sensor_msgs::Image::ConstPtr> rgbs;  // arrived, not yet used
  std::vector<sensor_msgs::PointCloud2::ConstPtr> scans;  // arrived, not yet used
  std::map<Stamp, std::vector<std::uint8_t>> depth_labels, lidar_labels;
  std::vector<std::string> warnings;
  const auto lookup = [&](const std::string& target, const std::string& source, const ::ros::Time& t) {
    return toEigen(tf_->lookupTransform(target, source, t).transform);
  };
  const auto emit = [&]() {
    BagFrame bf;
    bf.warnings.swap(warnings);
    PipelineFrame& fr = bf.frame;
    fr.stamp = pending->header.stamp.toSec();
    try {
      if (!info) throw ConversionError("no camera_info before the first depth image");
      const PinholeModel cam = toPinhole(*info);
      const auto rays = std::make_shared<SensorRays>(makeRays(cam));
      fr.T_odom_base = lookup(topics_.odom_frame, topics_.base_frame, pending->header.stamp);
      fr.measurements.push_back(fromDepthImage(cam, rays, depthFromImage(*pending, cam),
                                               lookup(topics_.odom_frame, pending->header.frame_id, pending->header.stamp),
                                               pending->header.frame_id));
      const Eigen::Isometry3d T_base_camera = lookup(topics_.base_frame, pending->header.frame_id, pending->header.stamp);
      if (auto h = hypotheses.find(key(pending->header.stamp)); h != hypotheses.end())
        for (const auto& p : h->second->hypotheses)
          fr.hypotheses.push_back({p.class_name, T_base_camera * toEigen(p.pose), p.score});
    } catch (const std::exception& e) {
      warnings.push_back(std::string("depth image at ") + std::to_string(pending->header.stamp.toSec()) +
                         " skipped: " + e.what());
      bf.warnings.insert(bf.warnings.end(), warnings.begin(), warnings.end());
      warnings.clear();
      pending.reset();
      return;  // the frame is not usable without its depth image
    }
    if (read_rgb_) {
      const Stamp k = key(pending->header.stamp);
      if (auto c = rgbs.find(k); c != rgbs.end()) {
        try {
          if (!rgb_info) throw ConversionError("no " + topics_.rgb_info + " before the colour image");
          RgbFrame rgb;
          rgb.camera = toPinhole(*rgb_info);
          rgb.rgb = rgbFromImage(*c->second, rgb.camera);
          rgb.T_base_camera = lookup(topics_.base_frame, c->second->header.frame_id, c->second->header.stamp);
          bf.rgb = std::move(rgb);
        } catch (const std::exception& e) {
          bf.warnings.push_back("colour image at " + std::to_string(pending->header.stamp.toSec()) + " skipped: " + e.what());
        }
      }
      rgbs.erase(rgbs.begin(), rgbs.upper_bound(k));
    }
    // The newest scan not later than the image.
    sensor_msgs::PointCloud2::ConstPtr scan;
    while (!scans.empty() && scans.front()->header.stamp <= pending->header.stamp) {
      scan = scans.front();
      scans.erase(scans.begin());
    }
    if (scan) {
      try {
        const SpinningLidarModel model = SpinningLidarModel::vlp16();
        static const auto lidar_rays = std::make_shared<SensorRays>(makeRays(SpinningLidarModel::vlp16()));
        fr.measurements.push_back(fromRanges(model, lidar_rays, rangesFromCloud(*scan, model),
                                             lookup(topics_.odom_frame, scan->header.frame_id, scan->header.stamp),
                                             scan->header.frame_id));
      } catch (const std::exception& e) {
        bf.warnings.push_back("LiDAR scan at " + std::to_string(scan->header.stamp.toSec()) + " skipped: " + e.what());
        scan.reset();
      }
    }
    const Stamp k = key(pending->header.stamp);
    if (auto o = truth_objects.find(k); o != truth_objects.end()) {
      GroundTruth gt;
      for (const auto& obj : o->second->objects) gt.objects.push_back({obj.id, obj.class_name, toEigen(obj.pose)});
      if (auto b = truth_base.find(k); b != truth_base.end()) gt.T_map_base = toEigen(b->second->pose);
      gt.labels.push_back(depth_labels.count(k) ? depth_labels[k] : std::vector<std::uint8_t>{});
      if (scan) {
        const Stamp ks = key(scan->header.stamp);
        gt.labels.push_back(lidar_labels.count(ks) ? lidar_labels[ks] : std::vector<std::uint8_t>{});
      }
      bf.truth = std::move(gt);
    }
    depth_labels.erase(depth_labels.begin(), depth_labels.upper_bound(k));
    pending.reset();
    f(bf);
  };
  for (const rosbag::MessageInstance& mi :
       rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{topics_.depth, topics_.depth_info, topics_.lidar, topics_.truth_depth_labels,
                                             topics_.truth_lidar_labels, topics_.rgb, topics_.rgb_info}))) {
    const std::string& topic = mi.getTopic();
    ::ros::Time stamp = mi.getTime();
    if (topic == topics_.depth_info) {
      info = mi.instantiate<sensor_msgs::CameraInfo>();
      continue;
    }
    if (topic == topics_.rgb_info) {
      rgb_info = mi.instantiate<sensor_msgs::CameraInfo>();
      continue;
    }
    if (topic == topics_.rgb) {
      if (read_rgb_) {
        if (auto img = mi.instantiate<sensor_msgs::Image>()) rgbs[key(img->header.stamp)] = img;
      }
      continue;
    }
    if (auto img = mi.instantiate<sensor_msgs::Image>()) stamp = img->header.stamp;
    if (auto pc = mi.instantiate<sensor_msgs::PointCloud2>()) stamp = pc->header.stamp;
    if (pending && stamp > pending->header.stamp) emit();
    try {
      if (topic == topics_.depth) {
        pending = mi.instantiate<sensor_msgs::Image>();
      } else if (topic == topics_.lidar) {
        scans.push_back(mi.instantiate<sensor_msgs::PointCloud2>());
      } else if (topic == topics_.truth_depth_labels) {
        const auto img = mi.instantiate<sensor_msgs::Image>();
        depth_labels[key(img->header.stamp)] = labelsOf(*img);
      } else if (topic == topics_.truth_lidar_labels) {
        const auto img = mi.instantiate<sensor_msgs::Image>();
        lidar_labels[key(img->header.stamp)] = labelsOf(*img);
      }
    } catch (const std::exception& e) {
      warnings.push_back(topic + " at " + std::to_string(stamp.toSec()) + " skipped: " + e.what());
    }
  }
  if (pending) emit();
}

}  // namespace sgt::ros
