// rostest, in the tracker's program (tracker.test): every kind of bad message at the running
// tracker node. After each kind the node must still be alive and track the five objects to 1 cm:
// the fixture's detections (1 cm noise per axis) are fused into the track filters, which weigh
// each fit at 1.1-1.5 m as a weaker measurement (far_fit_from_m), so a few millimetres of the
// detections' noise reach the published poses, most in the tracks made again after the jump back
// in time (up to 6 mm here).
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <scene_graph_tracker/AddTrack.h>
#include <scene_graph_tracker/RemoveTrack.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <thread>

#include "tracker_node_fixture.hpp"

namespace sgt {
namespace {

using test::TrackerNodeTest;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A valid 100-point x y z cloud; the cases below break one thing each.
sensor_msgs::PointCloud2 goodCloud() {
  sensor_msgs::PointCloud2 c;
  c.header.frame_id = "base_link", c.header.stamp = ::ros::Time::now();
  c.height = 1, c.width = 100;
  sensor_msgs::PointCloud2Modifier(c).setPointCloud2FieldsByString(1, "xyz");
  for (sensor_msgs::PointCloud2Iterator<float> x(c, "x"); x != x.end(); ++x)
    x[0] = 1, x[1] = x[2] = 0;
  return c;
}

std::vector<sensor_msgs::PointCloud2> badClouds() {
  std::vector<sensor_msgs::PointCloud2> out;
  auto add = [&](auto&& breakIt) {
    sensor_msgs::PointCloud2 c = goodCloud();
    breakIt(c);
    out.push_back(c);
  };
  add([](auto& c) { c.point_step = 0; });
  add([](auto& c) { c.fields[2].offset = 1000; });                      // beyond point_step
  add([](auto& c) { c.data.resize(10); });                              // shorter than its rows
  add([](auto& c) { c.width = 0xFFFFFFFFu, c.height = 0xFFFFFFFFu; });  // sizes that wrap
  add([](auto& c) { c.row_step = 1; });
  add([](auto& c) { c.fields[0].datatype = sensor_msgs::PointField::UINT8; });
  add([](auto& c) { c.fields.clear(); });
  add([](auto& c) { c.is_bigendian = 1; });  // valid, read byte-swapped
  add([](auto& c) {
    for (auto& b : c.data) b = 0xFF;  // NaN everywhere
  });
  return out;
}

scene_graph_tracker::PoseHypothesis hypothesis(const std::string& cls, double x, double qw) {
  scene_graph_tracker::PoseHypothesis h;
  h.class_name = cls, h.score = 0.9f;
  h.pose.position.x = x, h.pose.position.z = 1.0, h.pose.orientation.w = qw;
  return h;
}

class BadInputTest : public TrackerNodeTest {
 protected:
  // Three more frames with detections: outputs keep coming and every object is within 1 cm.
  void expectTracking(const std::string& after) {
    const std::size_t before = objects_count_;
    run(3, true);
    std::size_t matched = 0;
    EXPECT_GT(objects_count_, before) << "no output after " << after;
    EXPECT_LT(worstError(matched), 0.01) << "after " << after;
    EXPECT_EQ(matched, 5u) << "after " << after;
  }
  void publishHypotheses(std::vector<scene_graph_tracker::PoseHypothesis> hs) {
    scene_graph_tracker::PoseHypothesisArray a;
    a.header.stamp = ::ros::Time::now(), a.header.frame_id = "camera";
    a.hypotheses = std::move(hs);
    hyp_pub_.publish(a);
    sendFrame(false, depth_);
  }
};

TEST_F(BadInputTest, EveryBadMessageKindLeavesItAliveAndTracking) {
  run(8, true);
  expectTracking("the start");

  for (const auto& c : badClouds()) cloud_pub_.publish(c), ::ros::Duration(0.02).sleep();
  sendFrame(false, depth_);
  expectTracking("malformed point clouds");

  std::vector<float> short_depth(depth_.begin(), depth_.begin() + depth_.size() / 2);
  sendFrame(false, depth_, "bgr8");
  sendFrame(false, depth_, "32FC1", 60000);  // camera_info of a sensor that does not exist
  sendFrame(false, std::vector<float>(depth_.size(), static_cast<float>(kInf)));
  {
    sensor_msgs::Image img = ros::depthToImage(short_depth, cam_.width, cam_.height);
    img.header.stamp = ::ros::Time::now(), img.header.frame_id = "camera";
    sensor_msgs::CameraInfo info = ros::toCameraInfo(cam_);
    info.header = img.header;
    info.K[0] = kNaN;
    depth_pub_.publish(img), info_pub_.publish(info);  // short data and a NaN focal length
    img.data.clear(), img.width = img.height = 0;
    img.header.stamp += ::ros::Duration(0.01), info.header = img.header;
    depth_pub_.publish(img), info_pub_.publish(info);  // empty
  }
  expectTracking("bad images and camera_info");

  publishHypotheses({hypothesis("klt", kNaN, 1), hypothesis("klt", kInf, 1),
                     hypothesis("relay", 0.1, 0), hypothesis("relay", 0.1, kNaN),
                     hypothesis("no_such_class", 0.1, 1), hypothesis("", 0.1, 1)});
  auto nan_score = hypothesis("klt", 0.1, 1);
  nan_score.score = static_cast<float>(kNaN);
  publishHypotheses({nan_score});
  expectTracking("NaN and inf poses and quaternions");

  std::vector<scene_graph_tracker::PoseHypothesis> flood;  // 10^4, all near the true poses
  const Eigen::Isometry3d T_camera_map = (T_map_base_ * T_base_camera_).inverse();
  for (int i = 0; i < 10000; ++i) {
    const auto& [cls, T] = truth_[i % truth_.size()];
    scene_graph_tracker::PoseHypothesis h;
    h.class_name = cls, h.score = 0.5f;
    h.pose = ros::toPose(T_camera_map * T);
    flood.push_back(h);
  }
  publishHypotheses(flood);
  expectTracking("a flood of 10^4 hypotheses");
  EXPECT_LE(objects_->objects.size(), 10u) << "the flood made tracks";

  sendFrame(true, depth_, "32FC1", 640, "camera", ::ros::Time::now() - ::ros::Duration(20.0));
  EXPECT_TRUE(warnedWithin("time went back")) << "a bag loop resets the tracks, with a warning";
  run(8, true);
  expectTracking("a jump back in time");

  {  // stamped 5 s ahead, no TF that far: skipped, and it does not turn later frames into jumps
    sensor_msgs::Image img = ros::depthToImage(depth_, cam_.width, cam_.height);
    img.header.stamp = ::ros::Time::now() + ::ros::Duration(5.0), img.header.frame_id = "camera";
    sensor_msgs::CameraInfo info = ros::toCameraInfo(cam_);
    info.header = img.header;
    depth_pub_.publish(img), info_pub_.publish(info);
    spin(1.0);
  }
  const std::size_t resets = std::count_if(warnings_.begin(), warnings_.end(), [](auto& w) {
    return w.find("time went back") != std::string::npos;
  });
  expectTracking("a frame beyond its TF");
  EXPECT_EQ(std::count_if(warnings_.begin(), warnings_.end(),
                          [](auto& w) { return w.find("time went back") != std::string::npos; }),
            static_cast<long>(resets))
      << "one future frame made the next ones a jump back";

  scene_graph_tracker::AddTrack add;
  add.request.class_name = "no_such_class", add.request.pose.pose.orientation.w = 1;
  ASSERT_TRUE(::ros::service::call("/tracker/add_track", add));
  EXPECT_FALSE(add.response.success);
  add.request.class_name = "klt", add.request.pose.pose.position.x = kNaN;
  ASSERT_TRUE(::ros::service::call("/tracker/add_track", add));
  EXPECT_FALSE(add.response.success);
  add.request.pose.pose.position.x = 0, add.request.pose.header.frame_id = "nowhere";
  ASSERT_TRUE(::ros::service::call("/tracker/add_track", add));
  EXPECT_FALSE(add.response.success);
  scene_graph_tracker::RemoveTrack remove;
  remove.request.id = std::string(1 << 20, 'x');  // 1 MB
  ASSERT_TRUE(::ros::service::call("/tracker/remove_track", remove));
  EXPECT_FALSE(remove.response.success);
  expectTracking("services with bad arguments");

  std::atomic<bool> stop{false};
  std::atomic<int> calls{0};
  std::thread hammer([&] {  // dynamic_reconfigure while frames are processed
    for (int i = 0; !stop; ++i, ++calls) {
      dynamic_reconfigure::Reconfigure srv;
      dynamic_reconfigure::IntParameter rounds;
      rounds.name = "refine_rounds", rounds.value = 4 + i % 5;
      srv.request.config.ints.push_back(rounds);
      ::ros::service::call("/tracker/set_parameters", srv);
    }
  });
  run(6, true);
  stop = true;
  hammer.join();
  EXPECT_GT(calls.load(), 10);
  expectTracking("dynamic_reconfigure hammered");
}

}  // namespace
}  // namespace sgt
