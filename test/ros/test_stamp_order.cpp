// The live tracker's rule for frame stamps: process in order, drop duplicates and jitter, reset
// once on a jump back.
#include <gtest/gtest.h>

#include "scene_graph_tracker/ros/stamp_order.hpp"

namespace sgt::ros {
namespace {

TEST(StampOrder, ProcessesInOrderDropsDuplicatesAndJitterResetsOnceOnAJumpBack) {
  StampOrder order(0.5);
  EXPECT_EQ(order.check(10.0), StampVerdict::kProcess);
  EXPECT_EQ(order.check(10.033), StampVerdict::kProcess);
  EXPECT_EQ(order.check(10.033), StampVerdict::kDuplicate);
  EXPECT_EQ(order.check(10.032), StampVerdict::kJitter);  // 1 ms back: no reset
  EXPECT_EQ(order.check(9.6), StampVerdict::kJitter);     // within 0.5 s
  EXPECT_EQ(order.check(10.066), StampVerdict::kProcess);
  EXPECT_EQ(order.check(2.0), StampVerdict::kJumpBack);   // the bag looped
  EXPECT_EQ(order.check(2.033), StampVerdict::kProcess);  // and goes on from there, once
  order.reset();
  EXPECT_EQ(order.check(1.0), StampVerdict::kProcess);
}

TEST(StampOrder, AFrameThatIsNotTakenDoesNotMoveTheTimeLine) {
  StampOrder order(0.5);
  EXPECT_EQ(order.check(10.0), StampVerdict::kProcess);
  // One frame stamped far in the future that turns out bad (no TF for it): peeked, not taken.
  EXPECT_EQ(order.peek(500.0), StampVerdict::kProcess);
  EXPECT_EQ(order.check(10.033), StampVerdict::kProcess) << "no jump back after the bad frame";
  EXPECT_EQ(order.peek(2.0), StampVerdict::kJumpBack);
  order.take(2.0);
  EXPECT_EQ(order.peek(2.033), StampVerdict::kProcess);
}

}  // namespace
}  // namespace sgt::ros
