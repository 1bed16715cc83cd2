// Message builders shared by the bag writers of this library (simulate, sequence_to_bag).
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/message_traits.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <Eigen/Geometry>
#include <boost/make_shared.hpp>
#include <string>
#include <vector>

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {

inline std_msgs::Header header(const ::ros::Time& stamp, const char* frame) {
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  return h;
}

inline geometry_msgs::TransformStamped transform(const ::ros::Time& stamp, const char* parent,
                                                 const char* child, const Eigen::Isometry3d& T) {
  geometry_msgs::TransformStamped t;
  t.header = header(stamp, parent);
  t.child_frame_id = child;
  t.transform = toTransform(T);
  return t;
}

inline sensor_msgs::Image image(const std_msgs::Header& h, int width, int height,
                                const std::string& encoding, int channels,
                                std::vector<std::uint8_t> data) {
  sensor_msgs::Image img;
  img.header = h;
  img.width = width, img.height = height;
  img.encoding = encoding;
  img.is_bigendian = 0;
  img.step = channels * width;
  img.data = std::move(data);
  return img;
}

// Connection header of a latched topic (what rosbag record stores for /tf_static), as published
// by node `callerid`.
template <typename M>
boost::shared_ptr<::ros::M_string> latched(const M& msg, const char* callerid) {
  auto h = boost::make_shared<::ros::M_string>();
  (*h)["type"] = ::ros::message_traits::datatype(msg);
  (*h)["md5sum"] = ::ros::message_traits::md5sum(msg);
  (*h)["message_definition"] = ::ros::message_traits::definition(msg);
  (*h)["callerid"] = callerid;
  (*h)["latching"] = "1";
  return h;
}

}  // namespace sgt::ros
