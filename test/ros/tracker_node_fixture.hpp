// The tracker node's rostest fixture: simulated depth of the workbench (five catalog objects and
// a box the tracker does not know) published with noisy detections to the node that
// test/ros/tracker.test launches; the node's outputs and warnings collected.
//
// The fixture's subscriptions have a callback queue of their own, which only the test's thread
// spins (spin()): their state is never written while a test reads it. run() sends frames in
// lock-step with the node's output, so a slow node (a sanitizer build) sees every frame.
#pragma once

#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <random>
#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/noise.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace sgt::test {

inline Eigen::Isometry3d pose(const Eigen::Vector3d& t, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(t);
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

class TrackerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    nh_.setCallbackQueue(&queue_);
    const Building building = makeBuilding();  // the node's static_map (written by write_map)
    catalog_ = loadObjectCatalog("package://scene_graph_tracker/config/objects.yaml");
    world_.setStaticMap(std::make_shared<TriangleMesh>(building.mesh), 1);
    const Eigen::Vector3d top = building.workbench_top_centre.cast<double>();
    const std::vector<std::string> classes = {"multimeter", "screwdriver", "materialbox", "klt",
                                              "relay"};
    const double xs[5] = {-0.45, -0.2, 0.02, 0.3, 0.55}, yaws[5] = {0.3, -0.5, 0.1, 0.2, -0.2};
    for (std::size_t k = 0; k < classes.size(); ++k) {
      const ObjectClass& c = catalog_.get(classes[k]);
      const double half_z = 0.5 * c.box.sizes().z() - c.box.center().z();
      truth_.push_back(
          {classes[k], pose(top + Eigen::Vector3d(xs[k], 0.0, half_z + 0.001), yaws[k])});
      world_.addInstance(10 + static_cast<NodeId>(k), world_.addMesh(c.mesh), truth_.back().second);
    }
    world_.addInstance(
        30, world_.addMesh(std::make_shared<TriangleMesh>(makeBox({0.12f, 0.1f, 0.15f}))),
        pose(top + Eigen::Vector3d(-0.1, -0.25, 0.075), 0.0));
    world_.commit();
    T_map_base_ = pose(Eigen::Vector3d(top.x(), top.y() + 1.1, 0.0), -M_PI / 2);
    T_base_camera_ =
        T_map_base_.inverse() * opticalLookAt(T_map_base_ * Eigen::Vector3d(0.1, 0, 1.25), top);
    cam_ = PinholeModel::xtion();
    rays_ = std::make_shared<SensorRays>(makeRays(cam_));
    depth_ = depthImage(simulate(world_, *rays_, T_map_base_ * T_base_camera_), *rays_);

    depth_pub_ = nh_.advertise<sensor_msgs::Image>("/test/depth", 5);
    // tracker_robot.test: the node reads compressedDepth (<topic>/compressedDepth) and takes
    // map -> odom from TF, which this fixture then publishes (odom away from map).
    compressed_ = ::ros::param::param<std::string>("~depth_transport", "raw") == "compressedDepth";
    external_ = ::ros::param::param<std::string>("~localization", "own") == "external";
    if (external_) T_map_odom_ = pose(Eigen::Vector3d(0.3, -0.2, 0.0), 0.15);
    initialpose_pub_ =
        nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("/initialpose", 1, true);
    tf_sub_ = nh_.subscribe("/tf", 100, &TrackerNodeTest::onTf, this);
    depth_compressed_pub_ =
        nh_.advertise<sensor_msgs::CompressedImage>("/test/depth/compressedDepth", 5);
    info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("/test/camera_info", 5);
    hyp_pub_ = nh_.advertise<scene_graph_tracker::PoseHypothesisArray>("/test/pose_hypotheses", 5);
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/test/points", 5);
    objects_sub_ = nh_.subscribe("/tracker/tracked_objects", 5, &TrackerNodeTest::onObjects, this);
    markers_sub_ = nh_.subscribe("/tracker/markers", 5, &TrackerNodeTest::onMarkers, this);
    points_sub_ = nh_.subscribe("/tracker/unassigned_points", 5, &TrackerNodeTest::onPoints, this);
    rosout_sub_ = nh_.subscribe("/rosout", 100, &TrackerNodeTest::onLog, this);
    geometry_msgs::TransformStamped cam;
    cam.header.stamp = ::ros::Time::now(), cam.header.frame_id = "base_link",
    cam.child_frame_id = "camera";
    cam.transform = ros::toTransform(T_base_camera_);
    static_tf_.sendTransform(cam);
    // Wait for the node (it builds the building's BVH first) to take depth, camera_info and
    // detections and to publish its objects.
    auto connected = [&] {
      return depthPublisher().getNumSubscribers() > 0 && info_pub_.getNumSubscribers() > 0 &&
             hyp_pub_.getNumSubscribers() > 0 && objects_sub_.getNumPublishers() > 0;
    };
    for (int i = 0; i < 600 && !connected(); ++i) ::ros::Duration(0.1).sleep();
    ASSERT_TRUE(connected()) << "the tracker node did not come up";
  }

  // One frame: odom -> base at `stamp` (odom = map here), depth image and camera_info, and
  // optionally the detections.
  void sendFrame(bool hypotheses, const std::vector<float>& depth,
                 const std::string& encoding = "32FC1", int info_width = 640,
                 const std::string& frame = "camera", ::ros::Time stamp = ::ros::Time()) {
    if (stamp.isZero()) stamp = ::ros::Time::now();
    geometry_msgs::TransformStamped odom;
    odom.header.stamp = stamp, odom.header.frame_id = "odom", odom.child_frame_id = "base_link";
    odom.transform = ros::toTransform(T_map_odom_.inverse() * T_map_base_);
    tf_.sendTransform(odom);
    if (external_) {  // as amcl would
      geometry_msgs::TransformStamped map_odom;
      map_odom.header.stamp = stamp, map_odom.header.frame_id = "map";
      map_odom.child_frame_id = "odom", map_odom.transform = ros::toTransform(T_map_odom_);
      tf_.sendTransform(map_odom);
    }
    ::ros::Duration(0.02).sleep();  // let the transform arrive before the image
    sensor_msgs::Image img = ros::depthToImage(depth, cam_.width, cam_.height);
    img.encoding = encoding;
    img.header.stamp = stamp, img.header.frame_id = frame;
    sensor_msgs::CameraInfo info = ros::toCameraInfo(cam_);
    info.width = info_width;
    info.header = img.header;
    if (hypotheses) {
      scene_graph_tracker::PoseHypothesisArray h;
      h.header = img.header;
      for (const auto& [cls, T] : truth_) {
        Eigen::Isometry3d noisy = T;
        noisy.translation() += 0.01 * Eigen::Vector3d(g_(rng_), g_(rng_), g_(rng_));
        scene_graph_tracker::PoseHypothesis p;
        p.class_name = cls, p.score = 0.9f;
        p.pose = ros::toPose((T_map_base_ * T_base_camera_).inverse() * noisy);
        h.hypotheses.push_back(p);
      }
      hyp_pub_.publish(h);
    }
    ::ros::Duration(0.01).sleep();
    if (compressed_ && encoding == "32FC1")
      depth_compressed_pub_.publish(ros::compressDepthMillimetres(img.header, millimetres(depth)));
    else
      depth_pub_.publish(img);
    info_pub_.publish(info);
    spin(0.1);
  }

  // Runs the fixture's callbacks for `seconds` (at least once).
  void spin(double seconds) {
    const ::ros::WallTime end = ::ros::WallTime::now() + ::ros::WallDuration(seconds);
    do queue_.callAvailable(::ros::WallDuration(0.01));
    while (::ros::WallTime::now() < end);
  }

  // Spins until `done` holds, at most `seconds`; whether it holds.
  template <typename Done>
  bool spinUntil(Done done, double seconds = 30.0) {
    const ::ros::WallTime end = ::ros::WallTime::now() + ::ros::WallDuration(seconds);
    while (!done() && ::ros::WallTime::now() < end) spin(0.01);
    return done();
  }

  bool warnedWithin(const std::string& text, double seconds = 30.0) {
    return spinUntil([&] { return warned(text); }, seconds);
  }

  // `frames` frames at up to `rate_hz`, each once the node has published the previous one's
  // objects. A frame without output within 10 s is sent again, at most twice: a message can be
  // lost while a connection is being set up (the node's output to this test's new subscription
  // is connected a little after both ends are registered).
  void run(int frames, bool hypotheses, double rate_hz = 5.0) {
    for (int f = 0; f < frames; ++f) {
      const ::ros::Time stamp = ::ros::Time::now();
      bool answered = false;
      for (int attempt = 0; attempt < 3 && !answered; ++attempt) {
        sendFrame(hypotheses, depth_, "32FC1", 640, "camera", ::ros::Time::now());
        answered = spinUntil([&] { return objects_ && objects_->header.stamp >= stamp; }, 10.0);
      }
      EXPECT_TRUE(answered) << "no output for the frame at " << stamp << ", sent three times";
      spin(1.0 / rate_hz);
    }
    spin(0.5);
  }

  // Largest translation error of the tracked objects against the truth, matching by class.
  // `shift`: where the truth is expected, moved in the map frame.
  double worstError(std::size_t& matched,
                    const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) const {
    double worst = 0.0;
    matched = 0;
    if (!objects_) return 1e9;
    for (const auto& [cls, T] : truth_)
      for (const auto& o : objects_->objects)
        if (o.class_name == cls) {
          ++matched;
          worst = std::max(
              worst, (ros::toEigen(o.pose.pose).translation() - T.translation() - shift).norm());
        }
    return worst;
  }

  // Largest distance between an object's published map pose and its TF frame seen from the map
  // (the frame hangs below the object's scene-graph parent); 1e9 when a frame is missing.
  double worstTfError() const {
    if (!objects_) return 1e9;
    double worst = 0.0;
    for (const auto& o : objects_->objects) {
      try {
        const auto tf = tf_buffer_.lookupTransform(objects_->header.frame_id, o.id,
                                                   objects_->header.stamp, ::ros::Duration(1.0));
        worst = std::max(worst, (ros::toEigen(tf.transform).translation() -
                                 ros::toEigen(o.pose.pose).translation())
                                    .norm());
      } catch (const tf2::TransformException&) {
        return 1e9;
      }
    }
    return worst;
  }

  const ::ros::Publisher& depthPublisher() const {
    return compressed_ ? depth_compressed_pub_ : depth_pub_;
  }

  // Depth in metres (NaN: no return) as 16-bit millimetres (0: no return).
  cv::Mat millimetres(const std::vector<float>& depth) const {
    cv::Mat mm(cam_.height, cam_.width, CV_16UC1);
    for (int k = 0; k < cam_.width * cam_.height; ++k)
      mm.at<std::uint16_t>(k / cam_.width, k % cam_.width) =
          std::isfinite(depth[k]) ? static_cast<std::uint16_t>(std::lround(depth[k] * 1000.0f)) : 0;
    return mm;
  }

  bool warned(const std::string& text) const {
    for (const auto& w : warnings_)
      if (w.find(text) != std::string::npos) return true;
    return false;
  }

  void onObjects(const scene_graph_tracker::TrackedObjectArrayConstPtr& m) {
    objects_ = m, ++objects_count_;
  }
  void onMarkers(const visualization_msgs::MarkerArrayConstPtr& m) { markers_ = m; }
  // map -> odom from anyone but this test (the tracker publishes it only with its own
  // localization converged).
  void onTf(const ::ros::MessageEvent<tf2_msgs::TFMessage const>& e) {
    if (e.getPublisherName() == ::ros::this_node::getName()) return;
    for (const auto& t : e.getMessage()->transforms)
      foreign_map_odom_ += t.child_frame_id == "odom";
  }
  void onPoints(const sensor_msgs::PointCloud2ConstPtr& m) {
    unassigned_ = std::max<std::size_t>(unassigned_, m->width * m->height);
  }
  void onLog(const rosgraph_msgs::LogConstPtr& m) {
    if (m->level >= rosgraph_msgs::Log::WARN) warnings_.push_back(m->msg);
  }

  ::ros::CallbackQueue queue_;  // before nh_: its subscriptions leave it when they end
  ::ros::NodeHandle nh_;
  RaycastScene world_;
  ObjectCatalog catalog_;
  std::vector<std::pair<std::string, Eigen::Isometry3d>> truth_;
  Eigen::Isometry3d T_map_base_, T_base_camera_, T_map_odom_ = Eigen::Isometry3d::Identity();
  PinholeModel cam_;
  std::shared_ptr<SensorRays> rays_;
  std::vector<float> depth_;
  std::mt19937 rng_{3};
  std::normal_distribution<double> g_;
  ::ros::Publisher depth_pub_, depth_compressed_pub_, info_pub_, hyp_pub_, cloud_pub_;
  bool compressed_ = false, external_ = false;
  ::ros::Publisher initialpose_pub_;
  ::ros::Subscriber tf_sub_;
  std::size_t foreign_map_odom_ = 0;
  ::ros::Subscriber objects_sub_, markers_sub_, points_sub_, rosout_sub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_{tf_buffer_};
  scene_graph_tracker::TrackedObjectArrayConstPtr objects_;
  visualization_msgs::MarkerArrayConstPtr markers_;
  std::size_t unassigned_ = 0, objects_count_ = 0;
  std::vector<std::string> warnings_;
};

}  // namespace sgt::test
