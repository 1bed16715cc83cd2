// The evaluation report: the keys other tools read, means and recall computed by hand, identity
// switches, the pre-segmentation ratios and the hypotheses' share and errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "scene_graph_tracker/evaluation/report.hpp"

namespace sgt {
namespace {

PoseErrors errors(double add_s_m, double add_m, bool correct) {
  PoseErrors e;
  e.add_s = add_s_m, e.add = add_m, e.translation = add_m, e.rotation_deg = 1.0,
  e.correct = correct;
  e.add_or_adds = add_m, e.correct_add_or_adds = correct && add_m < 0.004;  // as for a plain class
  return e;
}

bool has(const std::string& json, const std::string& text) {
  return json.find(text) != std::string::npos;
}

TEST(EvaluationReport, KeysMeansRecallAndSwitches) {
  EvaluationReport r;
  StageTimes t;
  for (int f = 0; f < 4; ++f) {
    t.total_ms = 10.0 + f;  // 10, 11, 12, 13: median 11.5
    r.addFrame(f, t);
    r.addLocalization(f, 0.004, 0.1);
  }
  r.addObject(0, "klt_1", "klt", "klt_1", errors(0.002, 0.003, true));
  r.addObject(1, "klt_1", "klt", "klt_1", errors(0.004, 0.005, true));
  r.addObject(2, "klt_1", "klt", "", std::nullopt);  // missed: counts against recall
  PoseErrors far = errors(0.030, 0.040, false);
  far.displaced = true;
  far.crossed = true;                                       // on another crate
  r.addObject(3, "klt_1", "klt", "klt_2", far);             // another track: a switch
  r.addObject(4, "klt_1", "klt", "", std::nullopt, false);  // out of the camera's view: not scored
  r.addObject(5, "klt_1", "klt", "klt_3", errors(0.5, 0.5, false), false);  // nor a switch
  UnknownLabelCounts c;
  c.tp = 90, c.fp = 10, c.fn = 10, c.lidar_valid = 1000, c.lidar_unknown = 140;
  r.addPresegmentation(c);
  const std::string j = r.json();
  EXPECT_TRUE(has(j, "\"frames\": 4"));
  EXPECT_TRUE(has(j, "\"add_s_mean_mm\": 12")) << j;            // (2 + 4 + 30) / 3
  EXPECT_TRUE(has(j, "\"add_mean_mm\": 16")) << j;              // (3 + 5 + 40) / 3
  EXPECT_TRUE(has(j, "\"recall_adds_10\": 0.5")) << j;          // 2 correct of 4 evaluated
  EXPECT_TRUE(has(j, "\"add_or_adds_mean_mm\": 16")) << j;      // ADD: no declared symmetry
  EXPECT_TRUE(has(j, "\"recall_add_or_adds_10\": 0.25")) << j;  // 1 correct of 4 evaluated
  EXPECT_TRUE(has(j, "\"missed\": 1"));
  EXPECT_TRUE(has(j, "\"displaced\": 1,")) << j;  // frame 3: in the wrong place
  EXPECT_TRUE(has(j, "\"turned\": 1,")) << j;     // frame 1: in place, ADD too large
  EXPECT_TRUE(has(j, "\"crossed\": 1,")) << j;    // frame 3: on another object of its class
  EXPECT_TRUE(has(j, "\"out_of_view\": 2"));
  EXPECT_TRUE(has(j, "\"identity_switches\": 1"));
  EXPECT_TRUE(has(j, "\"translation_error_mean_mm\": 4"));  // localization: 4 mm every frame
  EXPECT_TRUE(has(j, "\"reduction\": 0.86"));
  EXPECT_TRUE(has(j, "\"precision\": 0.9"));
  EXPECT_TRUE(has(j, "\"recall\": 0.9"));
  EXPECT_TRUE(has(j, "\"frame_ms_median\": 11.5"));
  for (const char* key :
       {"\"objects\"", "\"rotation_error_mean_deg\"", "\"per_object\"", "\"localization\"",
        "\"presegmentation\"", "\"timing\"", "\"frame_ms_p95\""})
    EXPECT_TRUE(has(j, key)) << key;
  EXPECT_TRUE(has(r.markdown(), "| klt_1 | klt | 4 | 1 | 2 |"));
  EXPECT_TRUE(has(r.markdown(), " | 0.500 | 16.00 | 0.250 |\n"))
      << "recall with 3 digits (the goal is 0.99)\n"
      << r.markdown();
  EXPECT_TRUE(has(r.timeseriesCsv(), "object,3,klt_1,klt,30,40,"));
  EXPECT_TRUE(has(r.timeseriesCsv(), "object,4,klt_1,klt,,,,,,,,,,,,,,,,,,0,,,,,,,,,\n"))
      << "out of view, before the (track rows') pose columns\n"
      << r.timeseriesCsv();
}

TEST(EvaluationReport, FalsePositivesCountTrackFramesTracksAndClasses) {
  EvaluationReport r;
  r.addFrame(0, StageTimes{});
  const std::string none = r.json();
  EXPECT_TRUE(has(none, "\"false_positives\": 0,")) << none;
  EXPECT_TRUE(has(none, "\"false_tracks\": 0,"));
  EXPECT_FALSE(has(r.markdown(), "False positives"));
  r.addFalsePositive(0, "relay_4", "relay");  // e.g. on the walking person, two frames
  r.addFalsePositive(1, "relay_4", "relay");
  r.addFalsePositive(1, "klt_2", "klt");  // a duplicate
  const std::string j = r.json();
  EXPECT_TRUE(has(j, "\"false_positives\": 3,")) << j;
  EXPECT_TRUE(has(j, "\"false_tracks\": 2,")) << j;
  EXPECT_TRUE(has(j, "\"false_positives_by_class\": {\"klt\": 1, \"relay\": 2}")) << j;
  EXPECT_TRUE(has(r.markdown(), "3 track-frames of 1 klt track, 1 relay track.")) << r.markdown();
  EXPECT_TRUE(has(r.timeseriesCsv(), "false_positive,1,klt_2,klt,"));
}

TEST(EvaluationReport, HypothesesShareAndMedianErrorsPerObject) {
  EvaluationReport r;
  r.addFrame(0, StageTimes{});
  EXPECT_FALSE(has(r.json(), "\"hypotheses\"")) << "no key when nothing was scored";
  EXPECT_FALSE(has(r.markdown(), "Pose hypotheses"));
  PoseErrors e;
  for (const double t : {0.010, 0.030, 0.020})
    e.translation = t, e.rotation_deg = 100 * t, r.addHypothesis("klt_1", e, 10 * t);
  r.addHypothesis("klt_1", std::nullopt);  // in view, no hypothesis within the gate
  r.addHypothesis("screwdriver_1", std::nullopt);
  const std::string j = r.json();
  EXPECT_TRUE(
      has(j, "\"hypotheses\": {\n    \"evaluated\": 5,\n    \"found\": 3,\n    \"recall\": 0.6,"))
      << j;
  EXPECT_TRUE(has(
      j,
      "\"klt_1\": {\n        \"evaluated\": 4,\n        \"found\": 3,\n        \"recall\": 0.75,\n"
      "        \"translation_error_median_mm\": 20,\n        \"rotation_error_median_deg\": 2,\n"
      "        \"rotation_error_up_to_box_turns_median_deg\": 0.2\n"))
      << j;
  EXPECT_TRUE(has(j,
                  "\"screwdriver_1\": {\n        \"evaluated\": 1,\n        \"found\": 0,\n        "
                  "\"recall\": 0,\n"
                  "        \"translation_error_median_mm\": null"))
      << j;
  EXPECT_TRUE(has(r.markdown(), "| klt_1 | 4 | 3 | 0.750 | 20.0 | 2.0 |")) << r.markdown();
  EXPECT_TRUE(has(r.markdown(), "| screwdriver_1 | 1 | 0 | 0.000 | – | – |")) << r.markdown();
}

TEST(EvaluationReport, DepthResidualsAreMediansOverFramesPerObjectAndOverall) {
  EvaluationReport r;
  r.addObject(0, "cube", "cube", "cube_1", errors(0.002, 0.003, true));
  r.addSurfaceFit(0, "cube", 0.002, 0.005);
  r.addObject(1, "cube", "cube", "cube_1", errors(0.002, 0.003, true));
  r.addSurfaceFit(1, "cube", 0.004, 0.007);
  r.addObject(1, "dragon", "dragon", "", std::nullopt);
  r.addSurfaceFit(1, "dragon", std::nullopt, 0.020);  // untracked: the given pose only
  r.addSurfaceFit(2, "cube", 0.5, 0.5);               // no row of the cube at stamp 2: ignored
  const std::string j = r.json();
  EXPECT_TRUE(has(j, "\"depth_residual_median_mm\": 3,")) << j;      // all: 2, 4
  EXPECT_TRUE(has(j, "\"gt_depth_residual_median_mm\": 7,")) << j;   // all: 5, 7, 20
  EXPECT_TRUE(has(j, "\"gt_depth_residual_median_mm\": 6\n")) << j;  // the cube: 5, 7
  EXPECT_TRUE(has(j, "\"depth_residual_median_mm\": null")) << j;    // the dragon
  EXPECT_TRUE(has(r.markdown(), "| cube | 3 | 6 | 2 |")) << r.markdown();
  EXPECT_TRUE(has(r.timeseriesCsv(), ",cube_1,2,5,,,,1,,,,,,,,,\n")) << r.timeseriesCsv();
  EXPECT_FALSE(has(j, "depth_residual_alone")) << "no fit alone: no such keys";
  EvaluationReport none;
  none.addObject(0, "cube", "cube", "cube_1", errors(0.002, 0.003, true));
  EXPECT_FALSE(has(none.json(), "depth_residual")) << "reports without fits keep their keys";
  // With the mesh fitted alone: its median and the largest excess of the track over it.
  EvaluationReport alone;
  for (int k = 0; k < 3; ++k) {
    alone.addObject(k, "cube", "cube", "cube_1", errors(0.002, 0.003, true));
    alone.addSurfaceFit(k, "cube", 0.002 + 0.001 * k, 0.005, 0.002);
  }
  EXPECT_TRUE(has(alone.json(), "\"depth_residual_alone_median_mm\": 2,")) << alone.json();
  EXPECT_TRUE(has(alone.json(), "\"depth_residual_excess_max_mm\": 2")) << alone.json();
  EXPECT_TRUE(has(alone.timeseriesCsv(), ",1,,,,,,,,2,\n")) << alone.timeseriesCsv();
}

// Without ground truth: per confirmed track the medians of its fit support, inlier ratio and depth
// residual; the track count per frame; "track" rows with as many columns as the header and the
// track's pose.
TEST(EvaluationReport, TrackFiguresNeedNoGroundTruth) {
  EvaluationReport r;
  r.addFrame(0, {});
  r.tracks().add({0, "klt_1", "klt", true, 400, 0.9, 0.002});
  r.tracks().add({0, "relay_1", "relay", false, 10, 0.2, std::nullopt});  // tentative
  r.tracks().addFrame(0, 1);
  r.addFrame(1, {});
  const Eigen::Isometry3d T_map_klt(Eigen::Translation3d(1, 2, 3) *
                                    Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  r.tracks().add({1, "klt_1", "klt", true, 300, 0.7, 0.004, T_map_klt, 0.25});
  r.tracks().add({1, "relay_1", "relay", true, 50, 0.5, std::nullopt});
  r.tracks().addFrame(1, 2);
  const std::string j = r.json();
  EXPECT_TRUE(has(j, "\"count_median\": 1.5,")) << j;
  EXPECT_TRUE(has(j, "\"count_max\": 2,")) << j;
  EXPECT_TRUE(has(j,
                  "\"klt_1\": {\"class\": \"klt\", \"frames\": 2, \"inliers_median\": 350, "
                  "\"inlier_ratio_median\": 0.8, \"depth_residual_median_mm\": 3}"))
      << j;
  EXPECT_TRUE(has(j,
                  "\"relay_1\": {\"class\": \"relay\", \"frames\": 1, \"inliers_median\": 50, "
                  "\"inlier_ratio_median\": 0.5, \"depth_residual_median_mm\": null}"))
      << j;
  EXPECT_TRUE(has(r.markdown(), "| klt_1 | klt | 2 | 350.00 | 0.80 | 3.00 |")) << r.markdown();
  std::istringstream csv(r.timeseriesCsv());
  std::string line;
  std::getline(csv, line);
  const auto columns = std::count(line.begin(), line.end(), ',');
  int tracks = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), columns) << line;
    tracks += line.rfind("track,", 0) == 0;
  }
  EXPECT_EQ(tracks, 4);
  EXPECT_TRUE(has(
      r.timeseriesCsv(),
      "track,1,klt_1,klt,,,,,,,,,,,,klt_1,4,,300,0.7,1,,1,2,3,0,0,0.707106781,0.707106781,,0.25\n"))
      << r.timeseriesCsv();
}

}  // namespace
}  // namespace sgt
