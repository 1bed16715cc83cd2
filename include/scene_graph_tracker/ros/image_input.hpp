// An image topic as a message_filters source, read through image_transport. `transport` is "raw",
// "compressed" or "compressedDepth": what camera drivers and robot bags offer (a Tiago's Xtion
// publishes all three). When image_transport has no plugin for the transport (Debian ships only
// "raw"; Noetic's image_transport_plugins has all three), the compressed kinds are subscribed on
// <topic>/<transport> and decoded here (compressed_images.hpp), as the plugins would. A message
// that does not decode is reported to `on_error` and goes no further.
//
// Every image that does not reach the filter's output is counted:
// - A thread of its own receives the images (it only counts and stores them, so roscpp's queue
//   does not overflow) into a buffer of `queue_size`. When the node falls behind, the oldest
//   buffered image is dropped and counted as superseded, as roscpp's queue would drop it without
//   a count. The images are passed on (decoded, for the compressed kinds) one at a time on the
//   node handle's callback queue, so they stay serialised with the node's other callbacks.
// - Images lost before they reach the node (a dropped connection, a publisher's queue) are
//   counted from gaps in header.seq, which every roscpp publisher numbers: a seq that steps back
//   starts a new sequence (a restarted driver, a bag loop); unnumbered images (seq always 0) are
//   not counted as lost.
#pragma once

#include <image_transport/image_transport.h>
#include <message_filters/simple_filter.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace sgt::ros {

class ImageInput : public message_filters::SimpleFilter<sensor_msgs::Image> {
 public:
  using ErrorHandler = std::function<void(const std::string&)>;

  ImageInput() = default;
  ImageInput(const ImageInput&) = delete;
  ImageInput& operator=(const ImageInput&) = delete;
  ~ImageInput() { shutdown(); }

  // Throws std::invalid_argument for a transport other than the three, or a queue_size of 0.
  void subscribe(::ros::NodeHandle& nh, const std::string& topic, std::uint32_t queue_size,
                 const std::string& transport, ErrorHandler on_error);
  // Stops receiving and passing on images; waits for one being passed on. Call it before the
  // filters connected to this one are destroyed.
  void shutdown();
  // The subscribed topic, e.g. "/camera/depth/image_raw/compressedDepth".
  const std::string& topic() const { return topic_; }
  // How images arrive, for the log: through image_transport's plugin or decoded here.
  const std::string& description() const { return description_; }
  bool subscribed() const { return !topic_.empty(); }
  std::uint64_t received() const { return received_; }      // messages that arrived
  std::uint64_t lost() const { return lost_; }              // seq gaps before them
  std::uint64_t superseded() const { return superseded_; }  // dropped from the full buffer

 private:
  struct Pending {
    sensor_msgs::ImageConstPtr image;
    sensor_msgs::CompressedImageConstPtr compressed;
  };
  class Delivery;

  void subscribeTransport(::ros::NodeHandle& receiver, const std::string& topic,
                          std::uint32_t queue_size, const std::string& transport);
  void receive(Pending pending, const std_msgs::Header& header);  // the receiving thread
  void count(const std_msgs::Header& header);
  void deliverOne();  // on the node handle's callback queue
  void forward(const Pending& pending);
  std::uint64_t ownerId() const { return reinterpret_cast<std::uintptr_t>(this); }

  ::ros::CallbackQueue receive_queue_;
  std::unique_ptr<::ros::AsyncSpinner> receiver_;
  ::ros::CallbackQueueInterface* deliver_queue_ = nullptr;
  std::unique_ptr<image_transport::ImageTransport> transport_;
  image_transport::Subscriber image_sub_;
  ::ros::Subscriber compressed_sub_;
  ErrorHandler on_error_;
  std::string topic_, description_;
  std::atomic<std::uint64_t> received_{0}, lost_{0}, superseded_{0};
  std::uint32_t last_seq_ = 0;  // of the last message; the receiving thread only
  std::mutex mutex_;            // guards the three below
  std::deque<Pending> pending_;
  std::size_t capacity_ = 1;
  bool scheduled_ = false;  // a Delivery is on the callback queue
};

}  // namespace sgt::ros
