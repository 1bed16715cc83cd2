// An image topic as a message_filters source, read through image_transport. `transport` is "raw",
// "compressed" or "compressedDepth": what camera drivers and robot bags offer (a Tiago's Xtion
// publishes all three). When image_transport has no plugin for the transport (Debian ships only
// "raw"; Noetic's image_transport_plugins has all three), the compressed kinds are subscribed on
// <topic>/<transport> and decoded here (compressed_images.hpp), as the plugins would. A message
// that does not decode is reported to `on_error` and goes no further.
//
// Images lost before they reach the node (a subscriber queue that overflowed, a dropped
// connection) are counted from gaps in header.seq, which every roscpp publisher numbers: a seq
// that steps back starts a new sequence (a restarted driver, a bag loop); unnumbered images (seq
// always 0) are not counted as lost.
#pragma once

#include <image_transport/image_transport.h>
#include <message_filters/simple_filter.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace sgt::ros {

class ImageInput : public message_filters::SimpleFilter<sensor_msgs::Image> {
 public:
  using ErrorHandler = std::function<void(const std::string&)>;

  // Throws std::invalid_argument for a transport other than the three.
  void subscribe(::ros::NodeHandle& nh, const std::string& topic, std::uint32_t queue_size,
                 const std::string& transport, ErrorHandler on_error);
  // The subscribed topic, e.g. "/camera/depth/image_raw/compressedDepth".
  const std::string& topic() const { return topic_; }
  // How images arrive, for the log: through image_transport's plugin or decoded here.
  const std::string& description() const { return description_; }
  bool subscribed() const { return !topic_.empty(); }
  std::uint64_t received() const { return received_; }  // messages that arrived (decoded or not)
  std::uint64_t lost() const { return lost_; }          // seq gaps before them

 private:
  void onImage(const sensor_msgs::ImageConstPtr& image);
  void onCompressed(const sensor_msgs::CompressedImageConstPtr& compressed);
  void count(const std_msgs::Header& header);

  std::unique_ptr<image_transport::ImageTransport> transport_;
  image_transport::Subscriber image_sub_;
  ::ros::Subscriber compressed_sub_;
  ErrorHandler on_error_;
  std::string topic_, description_;
  std::atomic<std::uint64_t> received_{0}, lost_{0};
  std::uint32_t last_seq_ = 0;  // of the last message; its own callback thread only
};

}  // namespace sgt::ros
