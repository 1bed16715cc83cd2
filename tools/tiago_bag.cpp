// Rewrites a simulated bag (simulation/scenario_bag.hpp) the way a PAL Tiago records one: the
// head Xtion's topics and optical frame, RGB as JPEG (image_transport "compressed"), depth as
// 16-bit millimetre PNG ("compressedDepth"), and map -> odom on /tf as amcl publishes it (here
// from the ground truth, so the localization is exact). The LiDAR, odometry, ground truth and
// simulated detections are kept (frames renamed). The rostests of tiago.launch and
// replay.launch play such a bag.
//
//   rosrun scene_graph_tracker tiago_bag --bag IN.bag --output OUT.bag
#include <cv_bridge/cv_bridge.h>
#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <iostream>
#include <map>

#include "command_line.hpp"
#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/simulation/scenario_bag.hpp"

namespace {

namespace topics = sgt::ros::topics;
constexpr const char* kCamera = "xtion_rgb_optical_frame";

std::string renamed(const std::string& frame) {
  return frame == sgt::ros::frames::kCamera ? kCamera : frame;
}

class TiagoBag {
 public:
  explicit TiagoBag(const std::string& path) { out_.open(path, rosbag::bagmode::Write); }

  void add(const rosbag::MessageInstance& m) {
    const std::string& t = m.getTopic();
    if (t == topics::kRgb) return rgb(m);
    if (t == topics::kDepth) return depth(m);
    if (t == topics::kRgbInfo) return info(m, "/xtion/rgb/camera_info");
    if (t == topics::kDepthInfo) return info(m, "/xtion/depth_registered/camera_info");
    if (t == topics::kTf || t == topics::kTfStatic) return tf(m);
    if (t == topics::kGtBasePose) return basePose(m);
    if (t == topics::kHypotheses) {
      auto h = m.instantiate<scene_graph_tracker::PoseHypothesisArray>();
      h->header.frame_id = renamed(h->header.frame_id);
      return out_.write(t, m.getTime(), *h);
    }
    if (t == topics::kVelodyne || t == topics::kGtObjects) return out_.write(t, m.getTime(), m);
  }
  std::size_t mapOdomCount() const { return map_odom_; }

 private:
  void rgb(const rosbag::MessageInstance& m) {
    const auto img = m.instantiate<sensor_msgs::Image>();
    std_msgs::Header h = img->header;
    h.frame_id = kCamera;
    out_.write("/xtion/rgb/image_raw/compressed", m.getTime(),
               sgt::ros::compressRgbJpeg(h, cv_bridge::toCvShare(img, "rgb8")->image, 90));
  }
  void depth(const rosbag::MessageInstance& m) {
    const auto img = m.instantiate<sensor_msgs::Image>();
    const cv::Mat metres = cv_bridge::toCvShare(img, "32FC1")->image;
    cv::Mat mm(metres.size(), CV_16UC1);
    metres.forEach<float>([&](float z, const int* p) {
      mm.at<std::uint16_t>(p[0], p[1]) = std::isfinite(z) && z > 0 && z < 65.0f
                                             ? static_cast<std::uint16_t>(std::lround(z * 1000))
                                             : 0;
    });
    std_msgs::Header h = img->header;
    h.frame_id = kCamera;
    out_.write("/xtion/depth_registered/image_raw/compressedDepth", m.getTime(),
               sgt::ros::compressDepthMillimetres(h, mm));
  }
  void info(const rosbag::MessageInstance& m, const std::string& topic) {
    auto i = m.instantiate<sensor_msgs::CameraInfo>();
    i->header.frame_id = kCamera;
    out_.write(topic, m.getTime(), *i);
  }
  void tf(const rosbag::MessageInstance& m) {
    auto msg = m.instantiate<tf2_msgs::TFMessage>();
    for (auto& t : msg->transforms) {
      t.header.frame_id = renamed(t.header.frame_id), t.child_frame_id = renamed(t.child_frame_id);
      if (t.header.frame_id == sgt::ros::frames::kOdom &&
          t.child_frame_id == sgt::ros::frames::kBase) {
        odom_base_[t.header.stamp] = sgt::ros::toEigen(t.transform);
        mapOdom(t.header.stamp);
      }
    }
    // With the recorded connection header: /tf_static stays latched, as a robot's is, so that a
    // node that subscribes after the bag started still gets the sensors' transforms.
    out_.write(m.getTopic(), m.getTime(), *msg, m.getConnectionHeader());
  }
  void basePose(const rosbag::MessageInstance& m) {
    const auto p = m.instantiate<geometry_msgs::PoseStamped>();
    map_base_[p->header.stamp] = sgt::ros::toEigen(p->pose);
    out_.write(m.getTopic(), m.getTime(), *p);
    mapOdom(p->header.stamp);
  }
  // map -> odom at `stamp` once both the true base pose and the odometry of that stamp are in.
  void mapOdom(const ros::Time& stamp) {
    const auto a = map_base_.find(stamp), b = odom_base_.find(stamp);
    if (a == map_base_.end() || b == odom_base_.end()) return;
    tf2_msgs::TFMessage msg;
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp, t.header.frame_id = sgt::ros::frames::kMap;
    t.child_frame_id = sgt::ros::frames::kOdom;
    t.transform = sgt::ros::toTransform(a->second * b->second.inverse());
    msg.transforms.push_back(t);
    out_.write(topics::kTf, stamp, msg);
    map_base_.erase(a), odom_base_.erase(b), ++map_odom_;
  }

  rosbag::Bag out_;
  std::map<ros::Time, Eigen::Isometry3d> map_base_, odom_base_;
  std::size_t map_odom_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const sgt::cli::Flags flags("tiago_bag", "--bag IN.bag --output OUT.bag");
  std::string in, out;
  flags.parse(argc, argv, {{"--bag", &in}, {"--output", &out}});
  if (in.empty() || out.empty()) flags.fail("--bag and --output are required");
  try {
    rosbag::Bag bag(in, rosbag::bagmode::Read);
    TiagoBag tiago(out);
    std::size_t n = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) tiago.add(m), ++n;
    std::cerr << "tiago_bag: " << out << ": " << n << " messages read, " << tiago.mapOdomCount()
              << " map -> odom transforms\n";
  } catch (const std::exception& e) {
    std::cerr << "tiago_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
