#include "scene_graph_tracker/ros/image_input.hpp"

#include <boost/make_shared.hpp>
#include <stdexcept>

#include "scene_graph_tracker/ros/compressed_images.hpp"

namespace sgt::ros {
namespace {

// roscpp's queue before the receiving thread: that thread only stores pointers, so the queue
// only has to absorb a burst (a bag player or a driver publishing several images at once).
constexpr std::uint32_t kReceiveQueue = 32;

}  // namespace

// Passes the oldest buffered image on; the node handle's callback queue calls it.
class ImageInput::Delivery : public ::ros::CallbackInterface {
 public:
  explicit Delivery(ImageInput* input) : input_(input) {}
  CallResult call() override {
    input_->deliverOne();
    return Success;
  }

 private:
  ImageInput* input_;
};

void ImageInput::shutdown() {
  if (receiver_) receiver_->stop();  // no more receive() calls
  image_sub_.shutdown();
  compressed_sub_.shutdown();
  if (deliver_queue_) deliver_queue_->removeByID(ownerId());  // waits for a running Delivery
  deliver_queue_ = nullptr;
}

void ImageInput::subscribe(::ros::NodeHandle& nh, const std::string& topic,
                           std::uint32_t queue_size, const std::string& transport,
                           ErrorHandler on_error) {
  if (transport != "raw" && transport != "compressed" && transport != "compressedDepth")
    throw std::invalid_argument("image transport '" + transport + "' for '" + topic +
                                "': expected raw, compressed or compressedDepth");
  if (queue_size == 0) throw std::invalid_argument("image queue size 0 for '" + topic + "'");
  on_error_ = std::move(on_error);
  capacity_ = queue_size;
  deliver_queue_ = nh.getCallbackQueue();
  ::ros::NodeHandle receiver(nh);
  receiver.setCallbackQueue(&receive_queue_);
  subscribeTransport(receiver, topic, kReceiveQueue, transport);
  receiver_ = std::make_unique<::ros::AsyncSpinner>(1, &receive_queue_);
  receiver_->start();
}

void ImageInput::subscribeTransport(::ros::NodeHandle& receiver, const std::string& topic,
                                    std::uint32_t queue_size, const std::string& transport) {
  transport_ = std::make_unique<image_transport::ImageTransport>(receiver);
  try {
    image_sub_ = transport_->subscribe(
        topic, queue_size,
        [this](const sensor_msgs::ImageConstPtr& image) {
          receive({image, {}}, image->header);
        },
        {}, image_transport::TransportHints(transport));
    topic_ = image_sub_.getTopic();
    description_ = "image_transport '" + image_sub_.getTransport() + "' on " + topic_;
    return;
  } catch (const image_transport::TransportLoadException&) {
    if (transport == "raw") throw;  // image_transport's own: a broken installation
  }
  topic_ = receiver.resolveName(topic) + "/" + transport;
  compressed_sub_ = receiver.subscribe<sensor_msgs::CompressedImage>(
      topic_, queue_size, [this](const sensor_msgs::CompressedImageConstPtr& compressed) {
        receive({{}, compressed}, compressed->header);
      });
  description_ = topic_ + ", decoded here (no image_transport plugin for '" + transport + "')";
}

void ImageInput::count(const std_msgs::Header& header) {
  const std::uint64_t next = std::uint64_t{last_seq_} + 1;
  if (received_++ > 0 && header.seq > next) lost_ += header.seq - next;
  last_seq_ = header.seq;
}

void ImageInput::receive(Pending pending, const std_msgs::Header& header) {
  count(header);
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back(std::move(pending));
  if (pending_.size() > capacity_) pending_.pop_front(), ++superseded_;
  if (scheduled_) return;
  scheduled_ = true;
  deliver_queue_->addCallback(boost::make_shared<Delivery>(this), ownerId());
}

// One image per Delivery, and one Delivery queued at a time, so the callback queue never holds
// more than one of ours while the node is behind.
void ImageInput::deliverOne() {
  Pending next;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_.empty()) {
      scheduled_ = false;
      return;
    }
    next = std::move(pending_.front());
    pending_.pop_front();
    if (pending_.empty())
      scheduled_ = false;
    else
      deliver_queue_->addCallback(boost::make_shared<Delivery>(this), ownerId());
  }
  forward(next);
}

void ImageInput::forward(const Pending& pending) {
  if (pending.image) {
    signalMessage(::ros::MessageEvent<sensor_msgs::Image const>(pending.image));
    return;
  }
  sensor_msgs::ImagePtr image;
  try {
    image = boost::make_shared<sensor_msgs::Image>(decompress(*pending.compressed));
  } catch (const std::exception& e) {
    if (on_error_) on_error_("image on '" + topic_ + "' does not decode: " + e.what());
    return;
  }
  signalMessage(::ros::MessageEvent<sensor_msgs::Image const>(image));
}

}  // namespace sgt::ros
