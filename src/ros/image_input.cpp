#include "scene_graph_tracker/ros/image_input.hpp"

#include <boost/make_shared.hpp>
#include <stdexcept>

#include "scene_graph_tracker/ros/compressed_images.hpp"

namespace sgt::ros {

void ImageInput::subscribe(::ros::NodeHandle& nh, const std::string& topic,
                           std::uint32_t queue_size, const std::string& transport,
                           ErrorHandler on_error) {
  if (transport != "raw" && transport != "compressed" && transport != "compressedDepth")
    throw std::invalid_argument("image transport '" + transport + "' for '" + topic +
                                "': expected raw, compressed or compressedDepth");
  on_error_ = std::move(on_error);
  transport_ = std::make_unique<image_transport::ImageTransport>(nh);
  try {
    image_sub_ = transport_->subscribe(topic, queue_size, &ImageInput::onImage, this,
                                       image_transport::TransportHints(transport));
    topic_ = image_sub_.getTopic();
    description_ = "image_transport '" + image_sub_.getTransport() + "' on " + topic_;
    return;
  } catch (const image_transport::TransportLoadException&) {
    if (transport == "raw") throw;  // image_transport's own: a broken installation
  }
  topic_ = nh.resolveName(topic) + "/" + transport;
  compressed_sub_ = nh.subscribe(topic_, queue_size, &ImageInput::onCompressed, this);
  description_ = topic_ + ", decoded here (no image_transport plugin for '" + transport + "')";
}

void ImageInput::count(const std_msgs::Header& header) {
  const std::uint64_t next = std::uint64_t{last_seq_} + 1;
  if (received_++ > 0 && header.seq > next) lost_ += header.seq - next;
  last_seq_ = header.seq;
}

void ImageInput::onImage(const sensor_msgs::ImageConstPtr& image) {
  count(image->header);
  signalMessage(::ros::MessageEvent<sensor_msgs::Image const>(image));
}

void ImageInput::onCompressed(const sensor_msgs::CompressedImageConstPtr& compressed) {
  count(compressed->header);
  sensor_msgs::ImagePtr image;
  try {
    image = boost::make_shared<sensor_msgs::Image>(decompress(*compressed));
  } catch (const std::exception& e) {
    if (on_error_) on_error_("image on '" + topic_ + "' does not decode: " + e.what());
    return;
  }
  signalMessage(::ros::MessageEvent<sensor_msgs::Image const>(image));
}

}  // namespace sgt::ros
