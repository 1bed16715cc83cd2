// The simulator's bag round trip: config/scenarios/test_short.yaml (1 s) written with
// writeScenarioBag (what `simulate` calls) and read back with rosbag::View.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/simulation/scenario_bag.hpp"
#include "support.hpp"

namespace sgt::ros {
namespace {

class SimulateBag : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario_ = new sim::Scenario(
        sim::loadScenario(std::string(SGT_SOURCE_DIR) + "/config/scenarios/test_short.yaml"));
    path_ = test::tempDir() + "/short.bag";
    std::size_t calls = 0, last = 0, total = 0;
    summary_ = writeScenarioBag(*scenario_, path_, [&](std::size_t done, std::size_t n) {
      ++calls;
      EXPECT_EQ(done, last + 1);
      last = done, total = n;
    });
    EXPECT_EQ(calls, summary_.stamps);
    EXPECT_EQ(last, total);
  }
  static void TearDownTestSuite() { delete scenario_; }

  static const sim::Scenario& s() { return *scenario_; }
  static double timeOf(const ::ros::Time& stamp) { return stamp.toSec() - scenario_->start_time; }

  static sim::Scenario* scenario_;
  static std::string path_;
  static ScenarioBagSummary summary_;
};

sim::Scenario* SimulateBag::scenario_ = nullptr;
std::string SimulateBag::path_;
ScenarioBagSummary SimulateBag::summary_;

TEST_F(SimulateBag, TopicsCountsAndMonotonicStamps) {
  const std::size_t cams = sim::frameTimesNs(s().camera.rate, s().duration).size();
  const std::size_t scans = sim::frameTimesNs(s().lidar.rate, s().duration).size();
  ASSERT_EQ(cams, 30u);   // 30 Hz x 1 s
  ASSERT_EQ(scans, 10u);  // 10 Hz x 1 s
  EXPECT_EQ(summary_.camera_frames, cams);
  EXPECT_EQ(summary_.lidar_scans, scans);
  EXPECT_EQ(summary_.stamps, cams);  // LiDAR stamps are camera stamps too
  const std::map<std::string, std::size_t> expected = {{topics::kTfStatic, 1},
                                                       {topics::kMapOdomPrior, 1},
                                                       {topics::kTf, cams},
                                                       {topics::kRgb, cams},
                                                       {topics::kRgbInfo, cams},
                                                       {topics::kDepth, cams},
                                                       {topics::kDepthInfo, cams},
                                                       {topics::kVelodyne, scans},
                                                       {topics::kGtObjects, cams},
                                                       {topics::kGtBasePose, cams},
                                                       {topics::kGtDepthLabels, cams},
                                                       {topics::kGtVelodyneLabels, scans},
                                                       {topics::kHypotheses, cams}};

  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, std::size_t> count;
  std::map<std::string, ::ros::Time> last;
  for (const rosbag::MessageInstance& m : view) {
    const std::string topic = m.getTopic();
    ++count[topic];
    if (last.count(topic)) {
      EXPECT_GT(m.getTime(), last[topic]) << topic;  // strictly increasing per topic
    }
    last[topic] = m.getTime();
    EXPECT_GE(m.getTime().toSec(), s().start_time - 1e-6);
    EXPECT_LT(m.getTime().toSec(), s().start_time + s().duration);
  }
  EXPECT_EQ(count, expected);

  // /tf_static is latched, like rosbag record stores it.
  for (const rosbag::ConnectionInfo* c : view.getConnections())
    if (c->topic == topics::kTfStatic) {
      ASSERT_TRUE(c->header);
      EXPECT_EQ((*c->header)["latching"], "1");
    }
}

TEST_F(SimulateBag, ImagesAndLabelsAreConsistent) {
  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::uint64_t, sensor_msgs::Image> depth, labels, vlabels;
  std::map<std::uint64_t, sensor_msgs::PointCloud2> clouds;
  std::map<std::uint64_t, sensor_msgs::CameraInfo> infos;
  for (const rosbag::MessageInstance& m : view) {
    const std::string topic = m.getTopic();
    if (topic == topics::kDepth || topic == topics::kGtDepthLabels ||
        topic == topics::kGtVelodyneLabels || topic == topics::kRgb) {
      const auto img = m.instantiate<sensor_msgs::Image>();
      ASSERT_TRUE(img);
      EXPECT_EQ(img->header.stamp, m.getTime()) << topic;
      if (topic == topics::kRgb) {
        EXPECT_EQ(img->encoding, sensor_msgs::image_encodings::RGB8);
        EXPECT_EQ(img->header.frame_id, frames::kCamera);
        EXPECT_EQ(img->data.size(), 3u * img->width * img->height);
      }
      if (topic == topics::kDepth) depth[img->header.stamp.toNSec()] = *img;
      if (topic == topics::kGtDepthLabels) labels[img->header.stamp.toNSec()] = *img;
      if (topic == topics::kGtVelodyneLabels) vlabels[img->header.stamp.toNSec()] = *img;
    } else if (topic == topics::kDepthInfo) {
      const auto info = m.instantiate<sensor_msgs::CameraInfo>();
      infos[info->header.stamp.toNSec()] = *info;
      EXPECT_EQ(info->header.frame_id, frames::kCamera);
    } else if (topic == topics::kVelodyne) {
      const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
      EXPECT_EQ(cloud->header.frame_id, frames::kLidar);
      clouds[cloud->header.stamp.toNSec()] = *cloud;
    }
  }
  ASSERT_EQ(depth.size(), 30u);
  ASSERT_EQ(labels.size(), 30u);
  for (const auto& [stamp, img] : depth) {
    ASSERT_TRUE(infos.count(stamp));
    const PinholeModel cam = toPinhole(infos[stamp]);
    EXPECT_EQ(cam.width, s().camera.model.width);
    EXPECT_DOUBLE_EQ(cam.fx, s().camera.model.fx);
    EXPECT_EQ(img.encoding, sensor_msgs::image_encodings::TYPE_32FC1);
    EXPECT_EQ(img.header.frame_id, frames::kCamera);
    ASSERT_EQ(static_cast<int>(img.width), cam.width);
    ASSERT_EQ(static_cast<int>(img.height), cam.height);
    const std::vector<float> d = depthFromImage(img, cam);
    ASSERT_TRUE(labels.count(stamp));
    const sensor_msgs::Image& l = labels[stamp];
    EXPECT_EQ(l.encoding, sensor_msgs::image_encodings::MONO8);
    ASSERT_EQ(l.width, img.width);
    ASSERT_EQ(l.height, img.height);
    std::size_t returns = 0, per_label[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < d.size(); ++i) {
      const bool valid = std::isfinite(d[i]);
      returns += valid;
      ASSERT_LE(l.data[i], 3);
      EXPECT_EQ(l.data[i] == 0, !valid) << "pixel " << i;
      ++per_label[l.data[i]];
      if (valid) {
        EXPECT_GE(d[i], 0.3f);
        EXPECT_LE(d[i], 6.5f);
      }
    }
    EXPECT_GT(returns, d.size() / 2);
    EXPECT_GT(per_label[1], 0u);  // static map
    EXPECT_GT(per_label[2], 0u);  // catalog objects on the bench
    EXPECT_GT(per_label[3], 0u);  // the distractor box
  }

  ASSERT_EQ(clouds.size(), 10u);
  for (const auto& [stamp, cloud] : clouds) {
    EXPECT_EQ(cloud.height, 16u);
    EXPECT_EQ(cloud.width, 1824u);
    ASSERT_TRUE(vlabels.count(stamp));
    const sensor_msgs::Image& l = vlabels[stamp];
    ASSERT_EQ(l.width, 1824u);
    ASSERT_EQ(l.height, 16u);
    const SpinningLidarModel vlp16 = SpinningLidarModel::vlp16();
    const std::vector<float> r =
        measurementsFromCloud(cloud, vlp16, std::make_shared<SensorRays>(makeRays(vlp16)),
                              Eigen::Isometry3d::Identity())
            .range;
    std::size_t objects = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_EQ(l.data[i] == 0, !std::isfinite(r[i])) << "point " << i;
      objects += l.data[i] == 2;
    }
    EXPECT_GT(objects, 0u);
  }
}

TEST_F(SimulateBag, GroundTruthEqualsTheScenario) {
  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  rosbag::View view(
      bag, rosbag::TopicQuery(std::vector<std::string>{topics::kGtObjects, topics::kGtBasePose,
                                                       topics::kTf, topics::kTfStatic}));
  std::size_t arrays = 0, poses = 0, tfs = 0;
  Eigen::Isometry3d map_odom0 = Eigen::Isometry3d::Identity();
  for (const rosbag::MessageInstance& m : view) {
    const double t = timeOf(m.getTime());
    if (const auto a = m.instantiate<scene_graph_tracker::ObjectPoseArray>()) {
      ++arrays;
      EXPECT_EQ(a->header.frame_id, frames::kMap);
      EXPECT_EQ(a->header.stamp, m.getTime());
      ASSERT_EQ(a->objects.size(), s().objects.size());
      for (std::size_t i = 0; i < s().objects.size(); ++i) {
        EXPECT_EQ(a->objects[i].id, s().objects[i].id);
        EXPECT_EQ(a->objects[i].class_name, s().objects[i].class_name);
        const Eigen::Isometry3d truth = s().objects[i].trajectory.at(t);
        EXPECT_TRUE(toEigen(a->objects[i].pose).isApprox(truth, 1e-6))
            << s().objects[i].id << " at " << t;
      }
    } else if (const auto p = m.instantiate<geometry_msgs::PoseStamped>()) {
      ++poses;
      EXPECT_EQ(p->header.frame_id, frames::kMap);
      EXPECT_TRUE(toEigen(p->pose).isApprox(s().robot.at(t), 1e-6)) << t;
    } else if (const auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
      if (m.getTopic() == topics::kTfStatic) {
        ASSERT_EQ(tf->transforms.size(), 2u);
        EXPECT_EQ(tf->transforms[0].header.frame_id, frames::kBase);
        EXPECT_EQ(tf->transforms[0].child_frame_id, frames::kCamera);
        EXPECT_TRUE(toEigen(tf->transforms[0].transform).isApprox(s().camera.T_base_camera, 1e-9));
        EXPECT_EQ(tf->transforms[1].child_frame_id, frames::kLidar);
        EXPECT_TRUE(toEigen(tf->transforms[1].transform).isApprox(s().lidar.T_base_lidar, 1e-9));
        continue;
      }
      ASSERT_EQ(tf->transforms.size(), 1u);  // odometry only: map -> odom is the localizer's
      EXPECT_EQ(tf->transforms[0].header.frame_id, frames::kOdom);
      EXPECT_EQ(tf->transforms[0].child_frame_id, frames::kBase);
      const Eigen::Isometry3d odom_base = toEigen(tf->transforms[0].transform);
      if (tfs++ == 0) {
        // Odometry starts at the true start pose; the prior is it moved by the configured initial
        // error (in the robot's frame); map -> odom (own topic, once) stays near the identity.
        EXPECT_TRUE(odom_base.isApprox(s().robot.at(0.0), 1e-6));
        rosbag::View prior_view(bag, rosbag::TopicQuery(std::string(topics::kMapOdomPrior)));
        ASSERT_EQ(prior_view.size(), 1u);
        const auto p = prior_view.begin()->instantiate<geometry_msgs::TransformStamped>();
        ASSERT_TRUE(p);
        EXPECT_EQ(p->header.frame_id, frames::kMap);
        EXPECT_EQ(p->child_frame_id, frames::kOdom);
        map_odom0 = toEigen(p->transform);
        const Eigen::Vector3d e = s().noise.odom_initial_error;
        const Eigen::Isometry3d prior0 = map_odom0 * odom_base;
        EXPECT_TRUE(prior0.translation().isApprox(
            s().robot.at(0.0) * Eigen::Vector3d(e.x(), e.y(), 0), 1e-6));
        EXPECT_NEAR(Eigen::AngleAxisd(map_odom0.linear()).angle(), std::abs(e.z()), 1e-6);
      }
      // The odometry prior stays near the truth (noise of a 0.45 m drive): within 10 cm.
      const Eigen::Isometry3d prior = map_odom0 * odom_base;
      EXPECT_LT((prior.translation() - s().robot.at(t).translation()).norm(), 0.1) << t;
    }
  }
  EXPECT_EQ(arrays, 30u);
  EXPECT_EQ(poses, 30u);
  EXPECT_EQ(tfs, 30u);
}

TEST_F(SimulateBag, HypothesesAreTheTruthWithinTheConfiguredNoise) {
  const sim::DetectionSpec& d = s().detections;
  ASSERT_EQ(d.false_positives_per_frame, 0.0);  // every hypothesis belongs to an object
  ASSERT_EQ(d.miss_probability, 0.0);
  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(topics::kHypotheses));
  std::size_t frames = 0, total = 0;
  std::map<std::string, std::size_t> per_class;
  double sum_sq_t = 0.0;
  for (const rosbag::MessageInstance& m : view) {
    const auto a = m.instantiate<scene_graph_tracker::PoseHypothesisArray>();
    ASSERT_TRUE(a);
    ++frames;
    EXPECT_EQ(a->header.frame_id, frames::kCamera);
    EXPECT_EQ(a->header.stamp, m.getTime());
    const double t = timeOf(m.getTime());
    const Eigen::Isometry3d T_camera_map = (s().robot.at(t) * s().camera.T_base_camera).inverse();
    for (const auto& h : a->hypotheses) {
      ++total;
      ++per_class[h.class_name];
      EXPECT_GE(h.score, 0.0f);
      EXPECT_LE(h.score, 1.0f);
      const auto it =
          std::find_if(s().objects.begin(), s().objects.end(),
                       [&](const sim::ObjectSpec& o) { return o.class_name == h.class_name; });
      ASSERT_NE(it, s().objects.end()) << h.class_name;
      const Eigen::Isometry3d truth = T_camera_map * it->trajectory.at(t);
      const Eigen::Isometry3d est = toEigen(h.pose);
      const Eigen::Vector3d dt = est.translation() - truth.translation();
      EXPECT_LT(dt.cwiseAbs().maxCoeff(), 5.0 * d.sigma_t) << h.class_name << " at " << t;
      const double angle = Eigen::AngleAxisd(truth.linear().transpose() * est.linear()).angle();
      EXPECT_LT(angle, 6.0 * d.sigma_r_deg * M_PI / 180.0) << h.class_name << " at " << t;
      sum_sq_t += dt.squaredNorm();
    }
  }
  EXPECT_EQ(frames, 30u);
  EXPECT_EQ(total, summary_.hypotheses);
  // The big objects in full view are detected in every frame (no misses configured).
  EXPECT_EQ(per_class["klt"], 30u);
  EXPECT_EQ(per_class["multimeter"], 30u);
  // The translation noise has about the configured sigma per axis.
  ASSERT_GT(total, 50u);
  const double sigma = std::sqrt(sum_sq_t / (3.0 * static_cast<double>(total)));
  EXPECT_GT(sigma, 0.5 * d.sigma_t);
  EXPECT_LT(sigma, 1.5 * d.sigma_t);
}

TEST_F(SimulateBag, DeterministicGivenTheSeed) {
  const std::string again = test::tempDir() + "/again.bag";
  ScenarioBagOptions lz4;
  lz4.lz4 = true;
  writeScenarioBag(s(), again, {}, lz4);
  rosbag::Bag a(path_, rosbag::bagmode::Read), b(again, rosbag::bagmode::Read);
  rosbag::View va(a, rosbag::TopicQuery(topics::kDepth)), vb(b, rosbag::TopicQuery(topics::kDepth));
  ASSERT_EQ(va.size(), vb.size());
  auto ib = vb.begin();
  for (auto ia = va.begin(); ia != va.end(); ++ia, ++ib) {
    const auto x = ia->instantiate<sensor_msgs::Image>(), y = ib->instantiate<sensor_msgs::Image>();
    EXPECT_EQ(x->data, y->data);
  }
}

}  // namespace
}  // namespace sgt::ros
