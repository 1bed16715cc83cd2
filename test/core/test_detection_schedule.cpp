// The detector's schedule: every image while a track is tentative, at the settled interval while
// every track is confirmed; lost and removed tracks with a backoff; time jumps start over; a view
// that turned brings new images in at once.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/detection/detection_schedule.hpp"

namespace sgt::detection {
namespace {

constexpr double kFrame = 1.0 / 30.0;

// The frames (indices) of `count` images at 30 Hz from `start` on that the schedule runs on.
std::vector<int> runs(DetectionSchedule& s, double start, int count) {
  std::vector<int> out;
  for (int k = 0; k < count; ++k)
    if (s.due(start + k * kFrame)) out.push_back(k);
  return out;
}

const std::vector<ScheduledTrack> kConfirmed = {{"klt_1", TrackState::kConfirmed},
                                                {"relay_1", TrackState::kConfirmed}};

TEST(DetectionSchedule, WithoutIntervalsEveryImageIsDetected) {
  DetectionSchedule s;
  s.observe(0.0, kConfirmed);
  EXPECT_EQ(runs(s, 0.0, 5), (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(DetectionSchedule, ASettledSceneIsDetectedAtTheSettledInterval) {
  DetectionSchedule s({0.0, 0.5, 0.25});
  EXPECT_EQ(runs(s, 10.0, 3), (std::vector<int>{0, 1, 2})) << "no tracks yet: every image";
  s.observe(10.1, kConfirmed);
  EXPECT_TRUE(s.settled());
  // The last run was frame 2 (10.0667 s): the next 0.5 s = 15 frames after it (frame 17, the 14th
  // of these from frame 3 on), and so on.
  EXPECT_EQ(runs(s, 10.0 + 3 * kFrame, 40), (std::vector<int>{14, 29}));
}

TEST(DetectionSchedule, ATentativeTrackMakesTheNextImageDue) {
  DetectionSchedule s({0.0, 1.0, 0.25});
  s.observe(0.0, kConfirmed);
  EXPECT_TRUE(s.due(0.0));
  EXPECT_FALSE(s.due(kFrame));
  s.observe(kFrame, {{"klt_1", TrackState::kConfirmed}, {"relay_2", TrackState::kTentative}});
  EXPECT_FALSE(s.settled());
  EXPECT_TRUE(s.due(2 * kFrame));
  EXPECT_TRUE(s.due(3 * kFrame));
}

TEST(DetectionSchedule, ALostTrackIsLookedForLessOftenTheLongerItIsGone) {
  DetectionSchedule s({0.1, 1.0, 0.25});
  const std::vector<ScheduledTrack> lost = {{"klt_1", TrackState::kConfirmed},
                                            {"relay_1", TrackState::kLost}};
  s.observe(5.0, lost);
  EXPECT_DOUBLE_EQ(s.interval(), 0.1) << "just lost: the busy interval";
  s.observe(6.0, lost);
  EXPECT_DOUBLE_EQ(s.interval(), 0.25) << "lost 1 s ago: 0.25 s";
  s.observe(7.0, lost);
  EXPECT_DOUBLE_EQ(s.interval(), 0.5);
  s.observe(10.0, lost);
  EXPECT_DOUBLE_EQ(s.interval(), 1.0) << "no more often than a settled scene";
  EXPECT_TRUE(s.settled());
  s.observe(10.1, kConfirmed);
  s.observe(10.2, lost);
  EXPECT_DOUBLE_EQ(s.interval(), 0.1) << "found and lost again: from the start";
  s.observe(10.3, {});
  EXPECT_DOUBLE_EQ(s.interval(), 0.1) << "no track at all: look for objects";
}

TEST(DetectionSchedule, ARemovedTrackIsLookedForLikeALostOne) {
  DetectionSchedule s({0.1, 1.0, 0.25});
  s.observe(5.0, kConfirmed);
  EXPECT_TRUE(s.settled());
  const std::vector<ScheduledTrack> klt_only = {{"klt_1", TrackState::kConfirmed}};
  s.observe(5.1, klt_only);
  EXPECT_DOUBLE_EQ(s.interval(), 0.1) << "relay_1 was removed: it may come back";
  s.observe(7.1, klt_only);
  EXPECT_NEAR(s.interval(), 0.5, 1e-9);
  s.observe(9.1, klt_only);
  EXPECT_TRUE(s.settled()) << "removed 4 s ago";
  s.observe(9.2, {{"klt_1", TrackState::kConfirmed}, {"relay_2", TrackState::kTentative}});
  s.observe(9.3, klt_only);
  EXPECT_TRUE(s.settled()) << "a tentative track that went was never an object";
}

TEST(DetectionSchedule, AnImageBeforeTheLastRunIsDetected) {
  DetectionSchedule s({0.0, 10.0, 0.25});
  s.observe(100.0, kConfirmed);
  EXPECT_TRUE(s.due(100.0));
  EXPECT_FALSE(s.due(101.0));
  EXPECT_TRUE(s.due(3.0)) << "the bag started again";
  EXPECT_FALSE(s.due(4.0));
}

// A 640 x 480 window at (x, y) of a large scene of random grey and coloured blocks (a scene the
// camera pans over); another seed, another scene.
cv::Mat view(int x, int y, unsigned seed = 1) {
  cv::Mat scene(720, 960, CV_8UC3, cv::Scalar::all(128));
  cv::RNG rng(0x9E3779B97F4A7C15ull * seed);
  for (int k = 0; k < 600; ++k) {
    const cv::Point p(rng.uniform(0, 960), rng.uniform(0, 720));
    const cv::Size size(rng.uniform(16, 96), rng.uniform(16, 96));
    cv::rectangle(scene, cv::Rect(p, size),
                  cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256)),
                  cv::FILLED);
  }
  return scene(cv::Rect(x, y, 640, 480)).clone();
}

TEST(ViewNovelty, TheShareOfTheImageAPanBroughtIntoView) {
  ViewNovelty n;
  EXPECT_EQ(n.share(view(100, 100)), 1.0) << "nothing seen yet";
  n.remember(view(100, 100));
  EXPECT_LT(n.share(view(100, 100)), 0.02);
  EXPECT_NEAR(n.share(view(228, 100)), 128.0 / 640.0, 0.05) << "a fifth of the width";
  EXPECT_NEAR(n.share(view(36, 100)), 64.0 / 640.0, 0.05) << "the other way";
  EXPECT_NEAR(n.share(view(100, 196)), 96.0 / 480.0, 0.05) << "a fifth of the height";
  EXPECT_GT(n.share(view(100, 100, 2)), 0.6) << "another scene";
}

TEST(DetectionSchedule, AnImageThatShowsMuchNewIsDetectedWhateverTheInterval) {
  DetectionSchedule s({0.0, 10.0, 0.25, 0.15});
  s.observe(0.0, kConfirmed);
  EXPECT_TRUE(s.due(1.0, view(100, 100))) << "the first image";
  EXPECT_FALSE(s.due(1.1, view(100, 100)));
  EXPECT_FALSE(s.due(1.2, view(140, 100))) << "a sixteenth new";
  EXPECT_TRUE(s.due(1.3, view(200, 100))) << "a sixth new";
  EXPECT_FALSE(s.due(1.4, view(210, 100))) << "new since that run: little";
  EXPECT_FALSE(s.due(1.5)) << "no image: the interval alone";
}

}  // namespace
}  // namespace sgt::detection
