// rostest: feeds the tracker node simulated depth images of the workbench (five catalog objects
// and a box it does not know) with noisy detections, then bad input. Checks that the tracks
// converge to the truth and coast when detections stop, that markers and unassigned points
// appear, and that bad input (wrong encoding, camera_info size mismatch, all-NaN depth, missing
// TF) gives warnings while the node keeps tracking.
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <std_srvs/Empty.h>

#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "tracker_node_fixture.hpp"

namespace sgt {
namespace {

using test::TrackerNodeTest;

TEST_F(TrackerNodeTest, ConvergesCoastsAndSurvivesBadInput) {
  run(8, true);  // detections with 1 cm noise
  std::size_t matched = 0;
  EXPECT_LT(worstError(matched),
            0.005);  // refinement brings every object well below the detection noise
  EXPECT_EQ(matched, 5u);
  ASSERT_TRUE(markers_);
  std::size_t meshes = 0;
  for (const auto& m : markers_->markers)
    if (m.type == visualization_msgs::Marker::MESH_RESOURCE) {
      ++meshes;  // by the catalog's package:// URI: rviz on another machine finds it
      EXPECT_EQ(m.mesh_resource.rfind("package://scene_graph_tracker/meshes/", 0), 0u)
          << m.mesh_resource;
    }
  EXPECT_EQ(meshes, 5u);
  EXPECT_LT(worstTfError(), 1e-4);  // every object's TF frame where its message puts it
  EXPECT_GT(unassigned_, 200u);     // the unknown box on the bench

  run(6, false);  // detections stop: the tracks coast on refinement
  EXPECT_LT(worstError(matched), 0.005);
  EXPECT_EQ(matched, 5u);

  // Bad input, one of each; every one must be warned about.
  sendFrame(false, depth_, "rgb8");
  sendFrame(false, depth_, "32FC1", 320);
  sendFrame(false, std::vector<float>(depth_.size(), std::numeric_limits<float>::quiet_NaN()));
  sendFrame(false, depth_, "32FC1", 640, "nowhere");
  spin(2.0);
  EXPECT_TRUE(warnedWithin("rgb8")) << "wrong encoding";
  EXPECT_TRUE(warnedWithin("camera_info says")) << "size mismatch";
  EXPECT_TRUE(warnedWithin("nowhere")) << "missing TF";

  // ... and it keeps tracking.
  const std::size_t before = objects_count_;
  run(4, false);
  EXPECT_GT(objects_count_, before);
  EXPECT_LT(worstError(matched), 0.005);
  EXPECT_EQ(matched, 5u);

  // The node runs with the option structs' defaults: each run-time parameter, as
  // dynamic_reconfigure holds it (and last gave it to the pipeline), equals the schema's default
  // (config/tracker.yaml; search_orientations is tracker.launch's detector argument, false here as
  // by default).
  dynamic_reconfigure::Reconfigure current;
  ASSERT_TRUE(::ros::service::call("/tracker/set_parameters", current));
  const params::TrackerParameters defaults;
  std::size_t compared = 0;
  for (const auto& p : params::trackerSchema()) {
    if (!p.runtime) continue;
    const std::string name = params::reconfigureName(p.name);
    const params::Value d = p.get(defaults);
    for (const auto& x : current.response.config.bools) {
      if (x.name != name) continue;
      EXPECT_EQ(bool(x.value), std::get<bool>(d)) << name;
      ++compared;
    }
    for (const auto& x : current.response.config.ints) {
      if (x.name != name) continue;
      EXPECT_EQ(x.value, std::get<int>(d)) << name;
      ++compared;
    }
    for (const auto& x : current.response.config.doubles) {
      if (x.name != name) continue;
      if (p.single) {
        EXPECT_EQ(float(x.value), float(std::get<double>(d))) << name;
      } else {
        EXPECT_EQ(x.value, std::get<double>(d)) << name;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 70u);

  // Run-time reconfiguration (dynamic_reconfigure): fewer rounds, still tracking.
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::IntParameter rounds;
  rounds.name = "refine_rounds", rounds.value = 4;
  srv.request.config.ints.push_back(rounds);
  ASSERT_TRUE(::ros::service::call("/tracker/set_parameters", srv));
  bool applied = false;
  for (const auto& i : srv.response.config.ints)
    applied |= i.name == "refine_rounds" && i.value == 4;
  EXPECT_TRUE(applied);
  run(4, false);
  EXPECT_LT(worstError(matched), 0.005);
  EXPECT_EQ(matched, 5u);
}

// The static map and its furniture, latched for rviz: the building the node loaded, thinned
// evenly to at most 100,000 triangles (it has 411,698), and the workbench box with its name.
TEST_F(TrackerNodeTest, PublishesTheStaticMapAndFurnitureForRviz) {
  const auto m = ::ros::topic::waitForMessage<visualization_msgs::MarkerArray>(
      "/tracker/map_markers", ::ros::Duration(30.0));
  ASSERT_TRUE(m) << "no latched map markers";
  std::size_t points = 0;
  std::vector<std::string> names;
  for (const auto& k : m->markers) {
    EXPECT_EQ(k.header.frame_id, "map");
    if (k.ns == "static_map") points += k.points.size();
    if (k.ns == "furniture_names") names.push_back(k.text);
  }
  const std::size_t triangles = makeBuilding().mesh.triangleCount(),
                    step = (triangles + 99999) / 100000;
  EXPECT_EQ(points, 3 * ((triangles + step - 1) / step));
  EXPECT_EQ(names, std::vector<std::string>{"workbench"});
}

// With its own localization the tracker takes the robot's pose from initialpose (rviz "2D Pose
// Estimate"): told the robot stands 10 cm further along x, it moves map -> odom by that much (no
// LiDAR here, so nothing corrects it), starts the tracks over, and the objects appear moved with
// it. Its map -> odom is
// published only while the localization has converged: never here.
TEST_F(TrackerNodeTest, InitialPoseSetsTheMapPose) {
  run(6, true);
  geometry_msgs::PoseWithCovarianceStamped estimate;
  estimate.header.frame_id = "map", estimate.header.stamp = ::ros::Time::now();
  Eigen::Isometry3d claimed = T_map_base_;
  claimed.translation().x() += 0.1;
  estimate.pose.pose = ros::toPose(claimed);
  initialpose_pub_.publish(estimate);
  run(12, true);
  std::size_t matched = 0;
  EXPECT_LT(worstError(matched, Eigen::Vector3d(0.1, 0.0, 0.0)), 0.01);
  EXPECT_EQ(matched, 5u);
  EXPECT_EQ(foreign_map_odom_, 0u) << "map -> odom published without a converged localization";
  std_srvs::Empty reset;  // map -> odom back to identity for the next test
  ASSERT_TRUE(::ros::service::call("/tracker/reset", reset));
}

// tracker_robot.test, as on a Tiago with amcl: depth as compressedDepth (image_transport's plugin
// where it is installed, else the node's own decoder) and map -> odom from TF, 36 cm and 8.6 deg
// away from the odometry. The tracks sit on the truth in the map, the tracker publishes no
// map -> odom, and a message that does not decode is warned about.
TEST_F(TrackerNodeTest, TracksFromCompressedDepthWithExternalLocalization) {
  ASSERT_TRUE(compressed_ && external_) << "run by tracker_robot.test";
  run(8, true);
  std::size_t matched = 0;
  EXPECT_LT(worstError(matched), 0.005);
  EXPECT_EQ(matched, 5u);
  EXPECT_EQ(foreign_map_odom_, 0u) << "the tracker published map -> odom";
  sensor_msgs::CompressedImage broken;
  broken.header.stamp = ::ros::Time::now(), broken.header.frame_id = "camera";
  broken.format = "16UC1; compressedDepth png";
  broken.data.assign(40, 7);
  depth_compressed_pub_.publish(broken);
  spin(2.0);
  EXPECT_TRUE(warnedWithin("does not decode"));
}

}  // namespace
}  // namespace sgt

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_tracker");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
