// A nodelet as a plain node: loads it into this process under the node's name (for use without a
// nodelet manager). Remappings and private parameters pass through.
#pragma once

#include <nodelet/loader.h>
#include <ros/ros.h>

namespace sgt::cli {

inline int runNodelet(int argc, char** argv, const char* node_name, const char* nodelet_type) {
  ros::init(argc, argv, node_name);
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  if (!loader.load(ros::this_node::getName(), nodelet_type, remappings, {})) {
    ROS_FATAL("could not load %s (is the package built and on ROS_PACKAGE_PATH?)", nodelet_type);
    return 1;
  }
  ros::spin();
  return 0;
}

}  // namespace sgt::cli
