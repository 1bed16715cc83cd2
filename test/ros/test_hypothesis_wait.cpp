// HypothesisWait: a depth frame waits for the detector's array of its image while that may still
// come, and only then; frames go on in the order they came.
#include <gtest/gtest.h>

#include <boost/make_shared.hpp>

#include "scene_graph_tracker/ros/hypothesis_wait.hpp"

namespace sgt::ros {
namespace {

DepthFrame frame(double stamp_s) {
  auto m = boost::make_shared<sensor_msgs::Image>();
  m->header.stamp = ::ros::Time(stamp_s);
  return {m, boost::make_shared<sensor_msgs::CameraInfo>()};
}
::ros::WallTime wall(double s) { return ::ros::WallTime(1000.0 + s); }
std::vector<double> stamps(const std::vector<DepthFrame>& frames) {
  std::vector<double> out;
  for (const DepthFrame& f : frames) out.push_back(f.image->header.stamp.toSec());
  return out;
}

TEST(HypothesisWait, WithoutADetectorRunningFramesGoOnAtOnce) {
  HypothesisWait w(0.3);
  EXPECT_EQ(stamps(w.addDepth(frame(10.0), wall(0.0))), std::vector<double>{10.0});
  w.addHypotheses(::ros::Time(10.0), wall(0.1));
  // The detector went quiet for longer than a second: no more waiting.
  EXPECT_EQ(stamps(w.addDepth(frame(12.0), wall(2.0))), std::vector<double>{12.0});
  EXPECT_EQ(w.waited(), 0u);
}

TEST(HypothesisWait, AFrameWaitsForTheArrayOfItsImageAndThoseBeforeGoFirst) {
  HypothesisWait w(0.3);
  w.addHypotheses(::ros::Time(9.967), wall(0.0));
  EXPECT_TRUE(w.addDepth(frame(10.0), wall(0.01)).empty());
  EXPECT_TRUE(w.addDepth(frame(10.033), wall(0.04)).empty());
  EXPECT_TRUE(w.expired(wall(0.2)).empty());
  EXPECT_EQ(stamps(w.addHypotheses(::ros::Time(10.0), wall(0.21))), std::vector<double>{10.0});
  // The detector skipped 10.033's image: a later array ends its wait too.
  EXPECT_EQ(stamps(w.addHypotheses(::ros::Time(10.067), wall(0.25))), std::vector<double>{10.033});
  EXPECT_EQ(w.waited(), 2u);
  EXPECT_EQ(w.waitedInVain(), 0u);
}

TEST(HypothesisWait, AWaitEndsAfterMaxWaitOrWhenTooManyWait) {
  HypothesisWait w(0.3, 2);
  w.addHypotheses(::ros::Time(9.9), wall(0.0));
  EXPECT_TRUE(w.addDepth(frame(10.0), wall(0.0)).empty());
  EXPECT_TRUE(w.addDepth(frame(10.033), wall(0.1)).empty());
  EXPECT_EQ(stamps(w.addDepth(frame(10.067), wall(0.15))), std::vector<double>{10.0});  // keep 2
  EXPECT_EQ(stamps(w.expired(wall(0.41))), std::vector<double>{10.033});
  EXPECT_EQ(stamps(w.expired(wall(0.46))), std::vector<double>{10.067});
  EXPECT_TRUE(w.expired(wall(5.0)).empty());  // each handed out once
  EXPECT_EQ(w.waitedInVain(), 3u);
}

TEST(HypothesisWait, ZeroMaxWaitNeverWaits) {
  HypothesisWait w(0.0);
  w.addHypotheses(::ros::Time(9.9), wall(0.0));
  EXPECT_EQ(stamps(w.addDepth(frame(10.0), wall(0.0))), std::vector<double>{10.0});
}

}  // namespace
}  // namespace sgt::ros
