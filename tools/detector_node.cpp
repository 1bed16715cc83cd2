// The detector as a plain node: loads DetectorNodelet into its own process. Remappings and
// private parameters pass through.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "detector");
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  if (!loader.load(ros::this_node::getName(), "scene_graph_tracker/DetectorNodelet", remappings, {})) {
    ROS_FATAL("could not load scene_graph_tracker/DetectorNodelet (is the package built and on ROS_PACKAGE_PATH?)");
    return 1;
  }
  ros::spin();
  return 0;
}
