// Relation scoring: predicted edges renamed through the track -> object matching, judged against
// the declared relations active at the frame's time; undeclared kinds and pairs are not judged;
// frames near a declared boundary are not judged for it; untracked objects are not judged.
#include <gtest/gtest.h>

#include "scene_graph_tracker/evaluation/relation_score.hpp"

namespace sgt {
namespace {

using relations::Relation;

const std::vector<sim::RelationSpec> kDeclared = {
    {"relay_1", Relation::On, "workbench", 0.0, 15.5},
    {"relay_1", Relation::In, "klt_1", 17.8},
    {"klt_1", Relation::On, "workbench"},
};
const std::map<std::string, std::string> kMatch = {{"relay_3", "relay_1"}, {"klt_1", "klt_1"}};
const std::set<std::string> kFurniture = {"workbench"};

RelationCounts score(double t, const std::vector<relations::Edge>& edges,
                     const std::map<std::string, std::string>& match = kMatch) {
  return scoreRelations(t, kDeclared, edges, match, kFurniture);
}

TEST(RelationScore, TruePositivesThroughTheTrackMatching) {
  const RelationCounts c =
      score(5.0, {{"relay_3", Relation::On, "workbench"}, {"klt_1", Relation::On, "workbench"}});
  EXPECT_EQ(c.tp, 2u);
  EXPECT_EQ(c.fp, 0u);
  EXPECT_EQ(c.fn, 0u);
}

TEST(RelationScore, FalsePositivesOnlyForDeclaredKindsAndPairs) {
  // relay on klt: declared pair (relay_1, klt_1), declared kind "on", no declaration -> fp.
  // relay left_of klt: kind not declared -> not judged. klt on relay: pair not declared -> not
  // judged.
  const RelationCounts c = score(19.0, {{"relay_3", Relation::On, "klt_1"},
                                        {"relay_3", Relation::LeftOf, "klt_1"},
                                        {"klt_1", Relation::On, "relay_3"},
                                        {"klt_1", Relation::On, "workbench"}});
  EXPECT_EQ(c.tp, 1u);  // klt on workbench
  EXPECT_EQ(c.fp, 1u);  // relay on klt
  EXPECT_EQ(c.fn, 1u);  // relay in klt, missing
}

TEST(RelationScore, GraceAroundBoundariesAndUntrackedObjects) {
  // 15.3 s is within 0.5 s of the end of "relay on workbench": neither fn nor fp either way.
  EXPECT_EQ(score(15.3, {}).fn, 1u);  // only klt on workbench is missing
  EXPECT_EQ(
      score(15.7, {{"relay_3", Relation::On, "workbench"}, {"klt_1", Relation::On, "workbench"}})
          .fp,
      0u);
  EXPECT_EQ(
      score(16.5, {{"relay_3", Relation::On, "workbench"}, {"klt_1", Relation::On, "workbench"}})
          .fp,
      1u);
  // The relay not tracked: its declarations are not judged, edges naming unmatched tracks neither.
  const RelationCounts c = score(19.0, {{"relay_9", Relation::In, "klt_1"}}, {{"klt_1", "klt_1"}});
  EXPECT_EQ(c.tp + c.fp, 0u);
  EXPECT_EQ(c.fn, 1u);  // klt on workbench
}

}  // namespace
}  // namespace sgt
