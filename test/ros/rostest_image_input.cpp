// rostest (in rostest_tracker's process): ImageInput on a live topic. Every image it does not
// pass on is counted, whether the node fell behind (superseded in its buffer) or the image never
// arrived (a gap in header.seq); a sequence that starts again (a bag loop) is no loss.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <boost/make_shared.hpp>
#include <vector>

#include "scene_graph_tracker/ros/image_input.hpp"

namespace sgt {
namespace {

// Waits (up to 10 s) until `done` holds, for messages travelling on the live topic.
template <typename Done>
bool waitFor(Done done) {
  for (int i = 0; i < 1000 && !done(); ++i) ::ros::Duration(0.01).sleep();
  return done();
}

void publish(::ros::Publisher& pub, std::uint32_t seq) {
  // Published as a pointer to a subscriber in this process, the message is not serialised, so
  // roscpp keeps its seq (it numbers serialised messages itself).
  auto image = boost::make_shared<sensor_msgs::Image>();
  image->header.seq = seq;
  image->header.stamp = ::ros::Time(100.0 + seq);
  image->encoding = "32FC1";
  pub.publish(image);
}

TEST(ImageInput, CountsEveryImageItDoesNotPassOn) {
  ::ros::NodeHandle nh("~image_input");
  ::ros::CallbackQueue node_queue;  // the node's callbacks: run only when the test says so
  nh.setCallbackQueue(&node_queue);
  ros::ImageInput input;
  std::vector<std::uint32_t> passed_on;
  input.registerCallback(boost::function<void(const sensor_msgs::ImageConstPtr&)>(
      [&](const sensor_msgs::ImageConstPtr& image) { passed_on.push_back(image->header.seq); }));
  input.subscribe(nh, "images", 3, "raw", nullptr);
  ::ros::Publisher pub = ::ros::NodeHandle().advertise<sensor_msgs::Image>(input.topic(), 100);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }));

  // A node busy for 12 images: seq 1-10, then 13-14 (11 and 12 lost on the way).
  for (std::uint32_t seq = 1; seq <= 10; ++seq) publish(pub, seq);
  for (std::uint32_t seq = 13; seq <= 14; ++seq) publish(pub, seq);
  ASSERT_TRUE(waitFor([&] { return input.received() == 12; }));
  node_queue.callAvailable();
  while (!node_queue.isEmpty()) node_queue.callAvailable();
  EXPECT_EQ(passed_on, (std::vector<std::uint32_t>{10, 13, 14}));  // the newest three
  EXPECT_EQ(input.superseded(), 9u);
  EXPECT_EQ(input.lost(), 2u);
  EXPECT_EQ(input.received(), passed_on.size() + input.superseded());

  // The sequence starts again (a bag loop): nothing lost, the node keeps up.
  for (std::uint32_t seq = 1; seq <= 2; ++seq) {
    publish(pub, seq);
    ASSERT_TRUE(waitFor([&] { return input.received() == 12 + seq; }));
    node_queue.callAvailable();
  }
  EXPECT_EQ(passed_on, (std::vector<std::uint32_t>{10, 13, 14, 1, 2}));
  EXPECT_EQ(input.superseded(), 9u);
  EXPECT_EQ(input.lost(), 2u);
  input.shutdown();
}

}  // namespace
}  // namespace sgt
