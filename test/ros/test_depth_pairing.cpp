// DepthPairing: an RGB image waits for a depth image that may still come, and only then.
#include <gtest/gtest.h>

#include <boost/make_shared.hpp>

#include "scene_graph_tracker/ros/depth_pairing.hpp"

namespace sgt::ros {
namespace {

sensor_msgs::ImageConstPtr image(double stamp_s) {
  auto m = boost::make_shared<sensor_msgs::Image>();
  m->header.stamp = ::ros::Time(stamp_s);
  return m;
}
RgbFrame frame(double stamp_s) {
  return {image(stamp_s), boost::make_shared<sensor_msgs::CameraInfo>()};
}
::ros::WallTime wall(double s) { return ::ros::WallTime(1000.0 + s); }

TEST(DepthPairing, AnImageWhoseDepthCameFirstGoesOnAtOnce) {
  DepthPairing p(0.02, 0.1);
  EXPECT_FALSE(p.addDepth(image(10.0), wall(0.0)));
  const auto ready = p.addImage(frame(10.005), wall(0.001));
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].image->header.stamp, ::ros::Time(10.005));
  EXPECT_EQ(p.closest(::ros::Time(10.005))->header.stamp, ::ros::Time(10.0));
  EXPECT_EQ(p.waited(), 0u);
}

TEST(DepthPairing, AnImageWaitsForItsLateDepthImage) {
  DepthPairing p(0.02, 0.1);
  p.addDepth(image(10.0), wall(0.0));
  EXPECT_TRUE(p.addImage(frame(10.033), wall(0.01)).empty());  // its depth image may still come
  EXPECT_FALSE(p.expired(wall(0.05)));
  const auto done = p.addDepth(image(10.034), wall(0.06));
  ASSERT_TRUE(done);
  EXPECT_EQ(done->image->header.stamp, ::ros::Time(10.033));
  EXPECT_EQ(p.closest(::ros::Time(10.033))->header.stamp, ::ros::Time(10.034));
  EXPECT_EQ(p.waited(), 1u);
}

TEST(DepthPairing, AWaitEndsWhenItsDepthImageCannotComeAnyMore) {
  DepthPairing p(0.02, 0.1);
  p.addDepth(image(10.0), wall(0.0));
  EXPECT_TRUE(p.addImage(frame(10.033), wall(0.01)).empty());
  const auto done =
      p.addDepth(image(10.1), wall(0.02));  // later than 10.033 + 0.02: its own was lost
  ASSERT_TRUE(done);
  EXPECT_FALSE(p.closest(::ros::Time(10.033)));
}

TEST(DepthPairing, AWaitEndsAfterMaxWaitOrWithTheNextImage) {
  DepthPairing p(0.02, 0.1);
  p.addDepth(image(10.0), wall(0.0));
  EXPECT_TRUE(p.addImage(frame(10.033), wall(0.01)).empty());
  EXPECT_FALSE(p.expired(wall(0.10)));
  ASSERT_TRUE(p.expired(wall(0.12)));
  EXPECT_FALSE(p.expired(wall(0.5)));  // handed out once
  p.addDepth(image(10.05), wall(0.5));
  EXPECT_TRUE(p.addImage(frame(10.1), wall(0.51)).empty());
  const auto both = p.addImage(frame(10.133), wall(0.52));  // the older one goes on first
  ASSERT_EQ(both.size(), 1u);
  EXPECT_EQ(both[0].image->header.stamp, ::ros::Time(10.1));
}

TEST(DepthPairing, NoWaitWithoutALiveDepthStreamOrWithMaxWaitZero) {
  DepthPairing never(0.02, 0.1);
  EXPECT_EQ(never.addImage(frame(10.0), wall(0.0)).size(), 1u);  // no depth image so far
  DepthPairing stopped(0.02, 0.1);
  stopped.addDepth(image(10.0), wall(0.0));
  EXPECT_EQ(stopped.addImage(frame(12.0), wall(2.0)).size(), 1u);  // none for 2 s
  DepthPairing off(0.02, 0.0);
  off.addDepth(image(10.0), wall(0.0));
  EXPECT_EQ(off.addImage(frame(10.033), wall(0.01)).size(), 1u);
  EXPECT_EQ(off.waited(), 0u);
}

}  // namespace
}  // namespace sgt::ros
