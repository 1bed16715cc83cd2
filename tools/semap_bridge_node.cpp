// semap_bridge: the tracker's scene graph into the SEMAP database (PostgreSQL + PostGIS +
// SFCGAL) and spatial queries answered from it. See include/scene_graph_tracker/semap/bridge.hpp
// and config/semap.yaml.
#include <ros/ros.h>

#include "scene_graph_tracker/semap/bridge.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "semap_bridge");
  try {
    sgt::ros::SemapBridge bridge(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("semap_bridge: %s", e.what());
    return 1;
  }
  return 0;
}
