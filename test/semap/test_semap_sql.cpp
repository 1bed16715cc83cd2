// The SEMAP database's SQL relations (sql/semap_relations.sql) against the C++ engine
// (relations/spatial_relations.hpp) on random scenes, and the SQL answers for pose history and
// relation intervals. Each test program starts its own throw-away PostgreSQL server.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "pg_server.hpp"
#include "scene_graph_tracker/relations/spatial_relations.hpp"
#include "scene_graph_tracker/semap/db.hpp"

namespace sgt {
namespace {

using relations::Mode;
using relations::OrientedBox;
using relations::Relation;
using Triple = std::tuple<std::string, std::string, std::string>;

std::shared_ptr<semap::ClassShape> boxShape(const std::string& name, const Eigen::Vector3d& centre,
                                            const Eigen::Vector3d& half) {
  auto s = std::make_shared<semap::ClassShape>();
  s->name = name, s->box = Eigen::AlignedBox3d(centre - half, centre + half);
  return s;
}

Eigen::Isometry3d iso(const Eigen::Vector3d& t,
                      const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t, T.linear() = R;
  return T;
}

OrientedBox boxOf(const semap::InstancePose& o) {
  return relations::orientedBox(o.shape->box, o.T_world_object);
}

// Random scenes of a reference and two targets placed around it: beside one of its faces (inside
// or outside its projections), resting on top, inside, or anywhere within reach; references and
// targets rotated (yaw, tilt or any rotation). Scenes are 100 m apart.
class SceneMaker {
 public:
  explicit SceneMaker(std::uint32_t seed) : rng_(seed) {}

  std::vector<semap::InstancePose> scene(int index) {
    std::vector<semap::InstancePose> objects;
    const std::string tag = "s" + std::to_string(index) + "_";
    const Eigen::Vector3d origin(100.0 * (index % 10), 100.0 * (index / 10), 1.0);
    const Eigen::Vector3d r_half(u(0.05, 0.4), u(0.05, 0.4), u(0.03, 0.3));
    objects.push_back({tag + "ref", boxShape(tag + "ref_class", vec(-0.05, 0.05), r_half), "map",
                       iso(origin, rotation())});
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d t_half(u(0.01, 0.12), u(0.01, 0.12), u(0.01, 0.12));
      const Eigen::Vector3d t_centre = vec(-0.03, 0.03);
      const OrientedBox r = boxOf(objects.front());
      const bool aligned = coin();  // with R's axes: fits R's projections more often
      const Eigen::Isometry3d T_box =
          r.T_world_box * iso(placement(r_half, t_half, aligned),
                              aligned ? Eigen::Matrix3d::Identity() : rotation());
      objects.push_back({tag + "t" + std::to_string(k),
                         boxShape(tag + "t" + std::to_string(k) + "_class", t_centre, t_half),
                         "map", T_box * iso(-t_centre)});
    }
    return objects;
  }

 private:
  double u(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  bool coin() { return u(0, 1) < 0.5; }
  Eigen::Vector3d vec(double a, double b) { return Eigen::Vector3d(u(a, b), u(a, b), u(a, b)); }
  Eigen::Matrix3d rotation() {
    const double kind = u(0, 1);
    if (kind < 0.3)
      return Eigen::AngleAxisd(u(-M_PI, M_PI), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (kind < 0.6)
      return (Eigen::AngleAxisd(u(-M_PI, M_PI), Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(u(-0.3, 0.3), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
    return Eigen::Quaterniond(Eigen::Vector4d::Random().normalized()).toRotationMatrix();
  }
  // The target box's centre in the reference box's frame.
  Eigen::Vector3d placement(const Eigen::Vector3d& r_half, const Eigen::Vector3d& t_half,
                            bool aligned) {
    const double kind = u(0, 1);
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i)  // aligned: mostly within R's cross-section; else anywhere near it
      p[i] = aligned ? u(-1.15, 1.15) * std::max(r_half[i] - t_half[i], 0.0)
                     : u(-1.3, 1.3) * r_half[i];
    if (kind < 0.15) return p.cwiseProduct(Eigen::Vector3d::Constant(0.5));  // inside or crossing
    const int axis = static_cast<int>(u(0, 3)) % 3;
    const double sign = coin() ? 1.0 : -1.0;
    if (kind < 0.35) {  // resting on (or hovering just above) the top face
      p.z() = r_half.z() + t_half.z() + u(-0.005, 0.03);
      return p;
    }
    if (kind < 0.85) {  // beside a face, mostly within the extrusion length (3.5 x the extent)
      p[axis] = sign * (r_half[axis] + t_half[axis] +
                        u(-0.1, 1.1) * std::max(7.0 * r_half[axis] - 2.0 * t_half[axis], 0.0));
      return p;
    }
    return vec(-1.0, 1.0).cwiseProduct(r_half * 8.0);  // anywhere within reach
  }

  std::mt19937 rng_;
};

// The engine's answers for a scene; nullopt when one of them sits within `delta` of a boundary
// (grown / shrunk target box or distance threshold flips it), so the SQL may round either way.
std::optional<std::set<Triple>> coreAnswers(const std::vector<semap::InstancePose>& scene,
                                            Mode mode, double delta = 5e-4) {
  std::set<Triple> out;
  for (const auto& t : scene)
    for (const auto& r : scene) {
      if (&t == &r) continue;
      const OrientedBox tb = boxOf(t), rb = boxOf(r);
      OrientedBox grown = tb, shrunk = tb;
      grown.half_extents.array() += delta, shrunk.half_extents.array() -= delta;
      for (int k = 0; k < relations::kRelationCount; ++k) {
        const auto rel = static_cast<Relation>(k);
        relations::RelationOptions o, near = o, far = o;
        near.on_max_distance -= delta, far.on_max_distance += delta;
        const bool h = relations::holds(rel, mode, tb, rb, o);
        if (h != relations::holds(rel, mode, grown, rb, o) ||
            h != relations::holds(rel, mode, shrunk, rb, o) ||
            h != relations::holds(rel, mode, tb, rb, near) ||
            h != relations::holds(rel, mode, tb, rb, far))
          return std::nullopt;
        if (h) out.insert({t.id, relations::relationName(rel), r.id});
      }
    }
  return out;
}

// The engine's directional relations of t to r seen by a viewer at `viewer` (x, y) looking at r's
// origin; nullopt near a boundary, as above.
std::optional<std::set<std::string>> coreViewerAnswers(const semap::InstancePose& t,
                                                       const semap::InstancePose& r,
                                                       const Eigen::Vector2d& viewer, Mode mode,
                                                       double delta = 5e-4) {
  const Eigen::Vector2d sight = r.T_world_object.translation().head<2>() - viewer;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();  // x forward, level
  T_world_camera.linear() =
      Eigen::AngleAxisd(std::atan2(sight.y(), sight.x()), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  T_world_camera.translation() << viewer, r.T_world_object.translation().z();
  const OrientedBox tb = boxOf(t), rb = boxOf(r);
  OrientedBox grown = tb, shrunk = tb;
  grown.half_extents.array() += delta, shrunk.half_extents.array() -= delta;
  std::set<std::string> out;
  for (int k = 0; k < relations::kRelationCount; ++k) {
    const auto rel = static_cast<Relation>(k);
    if (!relations::isDirectional(rel)) continue;
    auto holds = [&](const OrientedBox& b) {
      return relations::holdsFromViewpoint(rel, mode, b, rb, T_world_camera, {},
                                           Eigen::Vector3d::UnitX());
    };
    const bool h = holds(tb);
    if (h != holds(grown) || h != holds(shrunk)) return std::nullopt;
    if (h) out.insert(relations::relationName(rel));
  }
  return out;
}

// One server for the program, a fresh database for each test.
class SemapSqlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (test::PgServer::missing().empty()) pg_ = std::make_unique<test::PgServer>();
  }
  static void TearDownTestSuite() { pg_.reset(); }
  void SetUp() override {
    SGT_REQUIRE_POSTGRES();
    db_ = std::make_unique<semap::SemapDb>(pg_->freshDatabase());
  }
  static std::unique_ptr<test::PgServer> pg_;
  std::unique_ptr<semap::SemapDb> db_;
};
std::unique_ptr<test::PgServer> SemapSqlTest::pg_;

TEST_F(SemapSqlTest, RelationsEqualTheCoreEngineOnRandomScenes) {
  SceneMaker maker(7);
  semap::Frame frame;
  frame.stamp = 1.0, frame.update_relations = false;
  std::map<Mode, std::set<Triple>> expected;
  int rejected = 0;
  for (int i = 0; i < 150; ++i) {
    for (;;) {
      const auto scene = maker.scene(i);
      const auto strict = coreAnswers(scene, Mode::Strict),
                 relaxed = coreAnswers(scene, Mode::Relaxed);
      if (!strict || !relaxed) {
        ++rejected;
        continue;
      }
      expected[Mode::Strict].insert(strict->begin(), strict->end());
      expected[Mode::Relaxed].insert(relaxed->begin(), relaxed->end());
      frame.objects.insert(frame.objects.end(), scene.begin(), scene.end());
      break;
    }
  }
  db_->writeFrame(frame);
  for (const auto& [mode, name] :
       {std::pair{Mode::Strict, "strict"}, std::pair{Mode::Relaxed, "relaxed"}}) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto rows = db_->relations("", "", "", name);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::set<Triple> got;
    std::map<std::string, int> per_relation;
    for (const auto& r : rows)
      got.insert({r.subject, r.relation, r.object}), ++per_relation[r.relation];
    EXPECT_EQ(got, expected[mode]) << name;
    for (int k = 0; k < relations::kRelationCount; ++k)
      EXPECT_GE(per_relation[relations::relationName(static_cast<Relation>(k))], 2)
          << name << " " << relations::relationName(static_cast<Relation>(k))
          << ": the scenes should show it";
    std::string counts;
    for (const auto& [relation, n] : per_relation)
      counts += " " + relation + " " + std::to_string(n);
    std::printf(
        "[ semap ] %s: %zu relations among %zu objects (%s), equal to the engine's; SQL %.0f ms\n",
        name, got.size(), frame.objects.size(), counts.c_str() + 1, ms);
  }
  std::printf("[ semap ] %d scenes regenerated for sitting within 0.5 mm of a boundary\n",
              rejected);
}

// semap_contains() (extent in the reference's frame) against SFCGAL's exact 3D difference, on
// rotated boxes: inside, crossing a face, outside, sharing faces (slow: few pairs).
TEST_F(SemapSqlTest, ContainmentAgreesWithSfcgalDifference) {
  const Eigen::Matrix3d R = Eigen::Quaterniond(0.8, 0.2, 0.4, 0.4).toRotationMatrix();
  const Eigen::Vector3d c(1, 2, 0.5);
  semap::Frame f;
  f.stamp = 1.0, f.update_relations = false;
  f.objects = {
      {"outer", boxShape("outer", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, 0.2, 0.1)), "map",
       iso(c, R)},
      {"inside", boxShape("small", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, 0.05, 0.02)),
       "map", iso(c + R * Eigen::Vector3d(0.1, 0, 0), R)},
      {"crossing", boxShape("small", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, 0.05, 0.02)),
       "map", iso(c + R * Eigen::Vector3d(0.28, 0, 0), R)},
      {"outside", boxShape("small", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, 0.05, 0.02)),
       "map", iso(c + Eigen::Vector3d(1, 0, 0), R)},
      {"same", boxShape("outer", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, 0.2, 0.1)), "map",
       iso(c, R)}};
  db_->writeFrame(f);
  const auto rows = db_->query(R"SQL(
    SELECT i.id, semap_holds('in', 'strict', i.id, 'outer'), ST_Volume(ST_3DDifference(i.box, o.box)) < 1e-9
    FROM instance i, instance o WHERE o.id = 'outer' AND i.id <> 'outer' ORDER BY i.id)SQL");
  ASSERT_EQ(rows.size(), 4u);
  const std::map<std::string, std::string> expected = {
      {"crossing", "f"}, {"inside", "t"}, {"outside", "f"}, {"same", "t"}};
  for (const auto& r : rows) {
    EXPECT_EQ(r[1], expected.at(r[0])) << r[0];
    EXPECT_EQ(r[1], r[2]) << r[0] << ": SFCGAL disagrees";
  }
}

Eigen::Isometry3d at(double x, double y, double z) { return iso(Eigen::Vector3d(x, y, z)); }

TEST_F(SemapSqlTest, WhereWasAndSinceComeFromTheHistory) {
  const auto table = boxShape("table", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.4, 0.05));
  const auto relay = boxShape("relay", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.03, 0.02, 0.05));
  auto frame = [&](double stamp, const Eigen::Isometry3d& T_relay) {
    semap::Frame f;
    f.stamp = stamp;
    f.objects = {{"table_1", table, "map", at(0, 0, 0.7)}, {"relay_1", relay, "table_1", T_relay}};
    db_->writeFrame(f);
  };
  frame(10.0, at(0.1, 0, 0.801));   // on the table (1 mm above its top)
  frame(11.0, at(0.12, 0, 0.801));  // still on it
  EXPECT_EQ(db_->objectsOn("table_1", ""), std::vector<std::string>{"relay_1"});
  auto since = db_->relationSince("relay_1", "on", "table_1", "strict");
  EXPECT_TRUE(since.holds);
  ASSERT_TRUE(since.since);
  EXPECT_NEAR(*since.since, 10.0, 1e-6);
  frame(12.0, at(0.12, 0, 1.0));  // lifted: above, no longer on
  since = db_->relationSince("relay_1", "on", "table_1", "strict");
  EXPECT_FALSE(since.holds);
  EXPECT_TRUE(db_->relationSince("relay_1", "above", "table_1", "strict").holds);
  frame(13.0, at(-0.2, 0.1, 0.801));  // put down again
  since = db_->relationSince("relay_1", "on", "table_1", "strict");
  ASSERT_TRUE(since.holds && since.since);
  EXPECT_NEAR(*since.since, 13.0, 1e-6);
  EXPECT_EQ(
      db_->query(
          "SELECT count(*) FROM relation_history WHERE subject = 'relay_1' AND relation = 'on' "
          "AND mode = 'strict' AND until IS NOT NULL")[0][0],
      "1");

  const auto p = db_->whereWas("relay_1", 11.5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->stamp, 11.0, 1e-6);
  EXPECT_EQ(p->parent, "table_1");
  EXPECT_LT((p->T_world_object.translation() - Eigen::Vector3d(0.12, 0, 0.801)).norm(), 1e-9);
  EXPECT_FALSE(db_->whereWas("relay_1", 9.0));
  EXPECT_FALSE(db_->whereWas("nobody", 11.0));

  EXPECT_EQ(db_->directionalRelations("relay_1", "table_1", "strict"),
            std::vector<std::string>{"above"});
  EXPECT_TRUE(db_->objectsIn("table_1", "strict").empty());
  const auto rel = db_->relations("relay_1", "", "", "strict");
  ASSERT_EQ(rel.size(), 2u);  // above, on (ordered by relation)
  EXPECT_EQ(rel[0].relation, "above");
  EXPECT_EQ(rel[1].relation, "on");
  EXPECT_THROW(db_->relations("", "under", "", "strict"), std::invalid_argument);
  EXPECT_THROW(db_->relations("", "", "", "fuzzy"), std::invalid_argument);
}

TEST_F(SemapSqlTest, InstancesMissingFromAFrameAreNotPresent) {
  const auto box = boxShape("crate", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.1, 0.1));
  semap::Frame f;
  f.stamp = 1.0;
  f.objects = {{"a", box, "map", at(0, 0, 0)}, {"b", box, "map", at(0, 0, 0.2005)}};
  db_->writeFrame(f);
  EXPECT_EQ(db_->objectsOn("a", "strict"), std::vector<std::string>{"b"});
  f.stamp = 2.0, f.objects.pop_back();
  db_->writeFrame(f);
  EXPECT_TRUE(db_->objectsOn("a", "strict").empty());
  EXPECT_EQ(db_->query("SELECT present FROM instance WHERE id = 'b'")[0][0], "f");
}

TEST_F(SemapSqlTest, ViewerRelationsEqualTheCoreEngineOnRandomScenes) {
  SceneMaker maker(11);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), range(1.0, 5.0);
  semap::Frame frame;
  frame.stamp = 1.0, frame.update_relations = false;
  struct Question {
    std::string t, r;
    Eigen::Vector2d viewer;
    std::set<std::string> expected[2];  // strict, relaxed
  };
  std::vector<Question> questions;
  std::map<std::string, int> seen;
  for (int i = 0; questions.size() < 200; ++i) {
    const auto scene = maker.scene(i);
    const double a = angle(rng), d = range(rng);
    const Eigen::Vector2d viewer = scene[0].T_world_object.translation().head<2>() +
                                   d * Eigen::Vector2d(std::cos(a), std::sin(a));
    for (int k = 1; k <= 2; ++k) {
      const auto strict = coreViewerAnswers(scene[k], scene[0], viewer, Mode::Strict),
                 relaxed = coreViewerAnswers(scene[k], scene[0], viewer, Mode::Relaxed);
      if (!strict || !relaxed) continue;  // within 0.5 mm of a boundary
      questions.push_back({scene[k].id, scene[0].id, viewer, {*strict, *relaxed}});
      for (const auto& n : *strict) ++seen[n];
      for (const auto& n : *relaxed) ++seen[n];
    }
    frame.objects.insert(frame.objects.end(), scene.begin(), scene.end());
  }
  db_->writeFrame(frame);
  for (const Question& q : questions)
    for (int m = 0; m < 2; ++m) {
      const auto got = db_->directionalRelations(q.t, q.r, m ? "relaxed" : "strict", q.viewer);
      EXPECT_EQ(std::set<std::string>(got.begin(), got.end()), q.expected[m])
          << q.t << " to " << q.r << " seen from " << q.viewer.transpose() << (m ? " relaxed" : "");
    }
  for (const char* n : {"left_of", "right_of", "in_front_of", "behind", "above", "below"})
    EXPECT_GE(seen[n], 5) << n << ": the scenes should show it";
  EXPECT_THROW(db_->directionalRelations("a", "b", "strict", Eigen::Vector2d(NAN, 0)),
               std::invalid_argument);
}

TEST_F(SemapSqlTest, ViewerLeftIsThePersonsLeft) {
  const auto table = boxShape("table", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.4, 0.05));
  const auto cup = boxShape("cup", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.04, 0.04, 0.05));
  semap::Frame f;
  f.stamp = 1.0;
  f.objects = {{"table_1", table, "map", at(0, 0, 0.7)}, {"cup_1", cup, "map", at(0, 0.9, 0.7)}};
  db_->writeFrame(f);  // the cup beside the table, on its +y side
  auto from = [&](double x, double y) {
    return db_->directionalRelations("cup_1", "table_1", "strict", Eigen::Vector2d(x, y));
  };
  EXPECT_EQ(from(-3, 0), std::vector<std::string>{"left_of"});  // looking along +x
  EXPECT_EQ(from(3, 0), std::vector<std::string>{"right_of"});  // looking along -x
  EXPECT_EQ(from(0, 3), std::vector<std::string>{"in_front_of"});
  EXPECT_EQ(from(0, -3), std::vector<std::string>{"behind"});
  EXPECT_EQ(db_->directionalRelations("cup_1", "table_1", "strict"),
            std::vector<std::string>{"left_of"});  // the table's own frame: +y is its left
}

TEST_F(SemapSqlTest, ARobotsCompleteFrameMarksOnlyItsOwnInstancesAbsent) {
  const auto box = boxShape("crate", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.1, 0.1));
  semap::Frame a, b;
  a.stamp = 1.0, a.robot = "a", a.objects = {{"a/crate_1", box, "map", at(0, 0, 0)}};
  b.stamp = 2.0, b.robot = "b", b.objects = {{"b/crate_1", box, "map", at(5, 0, 0)}};
  db_->writeFrame(a);
  db_->writeFrame(b);  // later and complete: robot a's crate stays present
  EXPECT_EQ(db_->query("SELECT id, robot FROM instance WHERE present ORDER BY id"),
            (std::vector<std::vector<std::string>>{{"a/crate_1", "a"}, {"b/crate_1", "b"}}));
  b.stamp = 3.0, b.objects.clear();
  db_->writeFrame(b);  // robot b sees nothing now
  EXPECT_EQ(db_->query("SELECT id FROM instance WHERE present"),
            (std::vector<std::vector<std::string>>{{"a/crate_1"}}));
}

TEST_F(SemapSqlTest, FurnitureIsFixedAndARelationReference) {
  // A table as a box from the floor to its top (0.75 m): SEMAP's "on" region above it is 3.5 x
  // that high, so it holds objects taller than a table top is thick.
  const Eigen::Vector3d half(0.6, 0.4, 0.375);
  semap::FixedObject table{"table_2", Eigen::AlignedBox3d(-half, half), at(2, 1, 0.375)};
  db_->writeFixed({table});
  const auto box = boxShape("klt", Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0.15, 0.1));
  semap::Frame f;
  f.stamp = 5.0;
  f.objects = {{"klt_1", box, "map", at(2.1, 1.0, 0.75 + 0.1005)}};
  db_->writeFrame(f);
  EXPECT_EQ(db_->objectsOn("table_2", "strict"), std::vector<std::string>{"klt_1"});
  f.stamp = 6.0;
  db_->writeFrame(f);  // a complete frame without the table leaves it present
  EXPECT_EQ(db_->query("SELECT present, fixed, class_name FROM instance WHERE id = 'table_2'")[0],
            (std::vector<std::string>{"t", "t", "furniture:table_2"}));
  EXPECT_TRUE(db_->relations("table_2", "", "", "strict").empty()) << "furniture is no subject";
  EXPECT_EQ(db_->query("SELECT count(*) FROM pose_history WHERE instance_id = 'table_2'")[0][0],
            "0");
  semap::FixedObject shelf{"shelf_1", Eigen::AlignedBox3d(-half, half), at(5, 1, 1.2)};
  db_->writeFixed({shelf, table});  // again, with a second piece: idempotent
  db_->writeFixed({shelf});         // the table left the map
  EXPECT_EQ(db_->query("SELECT id FROM instance WHERE fixed AND present")[0][0], "shelf_1");
  EXPECT_TRUE(db_->objectsOn("table_2", "strict").empty());
}

}  // namespace
}  // namespace sgt
