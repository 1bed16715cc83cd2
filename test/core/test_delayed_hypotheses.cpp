// Hypotheses delivered frames late, moved through the odometry into the receiving frame's base.
#include <gtest/gtest.h>

#include "scene_graph_tracker/detection/delayed_hypotheses.hpp"

namespace sgt::detection {
namespace {

Eigen::Isometry3d along(double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = x;
  return T;
}

// A robot driving 1 cm per frame along x sees an object at the odometry's x = 1 m.
TEST(DelayedHypotheses, ComeOutLateInTheBaseFrameOfTheFrameThatReceivesThem) {
  DelayedHypotheses delay(2);
  std::vector<std::vector<PoseHypothesis>> out;
  for (int f = 0; f < 4; ++f) {
    const double x = 0.01 * f;
    PoseHypothesis h{"klt", along(1.0 - x), 0.9, false};
    out.push_back(delay.pass({h}, along(x)));
  }
  EXPECT_TRUE(out[0].empty());
  EXPECT_TRUE(out[1].empty());
  ASSERT_EQ(out[2].size(), 1u);  // frame 0's detection
  ASSERT_EQ(out[3].size(), 1u);  // frame 1's
  EXPECT_NEAR(out[2][0].T_base_object.translation().x(), 1.0 - 0.02, 1e-12);
  EXPECT_NEAR(out[3][0].T_base_object.translation().x(), 1.0 - 0.03, 1e-12);
  EXPECT_EQ(out[3][0].class_name, "klt");
}

TEST(DelayedHypotheses, NoDelayPassesThemThrough) {
  DelayedHypotheses now(0);
  const auto out = now.pass({{"relay", along(0.5), 0.8, true}}, along(3.0));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].T_base_object.translation().x(), 0.5, 1e-12);
  EXPECT_TRUE(out[0].up_to_box_half_turns);
}

}  // namespace
}  // namespace sgt::detection
