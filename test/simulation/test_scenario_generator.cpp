// The scenario generator: containers found by rays, every generated scenario loads as `simulate`
// reads it, and its ground truth is physically consistent (no interpenetrating objects at rest,
// carrying at most 1 m/s, "in" inside the container, "on" resting on its support), deterministic
// per seed, and the suite's features all occur.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/simulation/scenario_generator.hpp"
#include "support.hpp"

namespace sgt::sim {
namespace {

class ScenarioGeneratorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    catalog_ =
        new ObjectCatalog(loadObjectCatalog(resolveResourcePath(GeneratorOptions().catalog)));
    shapes_ = new std::map<std::string, ClassShape>(classShapes(*catalog_));
  }
  static std::string yaml(std::uint32_t seed) {
    std::ostringstream s;
    writeScenarioYaml(generateScenario({}, *shapes_, seed, "t"), {}, s);
    return s.str();
  }
  static Scenario load(std::uint32_t seed) {
    const std::string path = test::tempDir() + "/generated_" + std::to_string(seed) + ".yaml";
    std::ofstream(path) << yaml(seed);
    return loadScenario(path);
  }
  static ObjectCatalog* catalog_;
  static std::map<std::string, ClassShape>* shapes_;
};
ObjectCatalog* ScenarioGeneratorTest::catalog_ = nullptr;
std::map<std::string, ClassShape>* ScenarioGeneratorTest::shapes_ = nullptr;

TEST_F(ScenarioGeneratorTest, RaysFindTheOpenBinAsTheOnlyContainerAmongClosedShapes) {
  const ClassShape& klt = shapes_->at("klt");
  ASSERT_TRUE(klt.container);
  EXPECT_LT(klt.floor, klt.box_min.z() + 0.2 * klt.height());
  EXPECT_GT(klt.inner_half.x(), 0.5 * klt.halfFootprint().x());
  EXPECT_LT(klt.inner_half.x(), klt.halfFootprint().x());
  EXPECT_LT(klt.inner_half.y(), klt.halfFootprint().y());
  for (const char* closed : {"multimeter", "relay", "screwdriver"})
    EXPECT_FALSE(shapes_->at(closed).container) << closed;
}

TEST_F(ScenarioGeneratorTest, SameSeedSameFileOtherSeedOtherFile) {
  EXPECT_EQ(yaml(5), yaml(5));
  EXPECT_NE(yaml(5), yaml(6));
}

// Bottom and footprint of an object at time t (upright objects: rotation about z only).
struct Placed {
  Eigen::Isometry3d T;
  Eigen::AlignedBox3f box;
  double bottom() const { return T.translation().z() + box.min().z(); }
  double top() const { return T.translation().z() + box.max().z(); }
  bool contains(const Eigen::Vector3d& p_world, double margin) const {
    const Eigen::Vector3f p = (T.inverse() * p_world).cast<float>();
    return (p.array() >= box.min().array() - margin).all() &&
           (p.array() <= box.max().array() + margin).all();
  }
};

Placed placed(const Scenario& s, const ObjectSpec& o, double t) {
  return {o.trajectory.at(t), s.catalog->get(o.class_name).box};
}

void expectConsistent(const Scenario& s) {
  ASSERT_GE(s.objects.size(), 3u);
  ASSERT_LE(s.objects.size(), 10u);
  std::map<std::string, int> per_class;
  for (const ObjectSpec& o : s.objects) EXPECT_LE(++per_class[o.class_name], 4) << o.id;
  const double bench = s.workbench->z();
  for (const RelationSpec& r : s.relations) {
    const double to = std::min(r.to, s.duration), t = 0.5 * (r.from + to);
    const Placed subject = placed(s, *s.findObject(r.subject), t);
    if (r.relation == relations::Relation::In) {
      const Placed container = placed(s, *s.findObject(r.object), t);
      EXPECT_TRUE(container.contains(subject.T.translation(), 0.0))
          << r.subject << " in " << r.object;
      EXPECT_GT(subject.bottom(), container.bottom()) << r.subject;
      continue;
    }
    const double support =
        r.object == kWorkbenchName ? bench : placed(s, *s.findObject(r.object), t).top();
    EXPECT_NEAR(subject.bottom(), support, 0.003) << r.subject << " on " << r.object << " at " << t;
  }
  for (const ObjectSpec& o : s.objects) {
    const auto& keys = o.trajectory.keys();
    for (std::size_t i = 1; i < keys.size(); ++i)
      EXPECT_LE((keys[i].position - keys[i - 1].position).norm() / (keys[i].t - keys[i - 1].t),
                1.0 + 1e-6)
          << o.id << " between keys " << i - 1 << " and " << i;
  }
}

// Resting objects never share space: at t = 0, two objects' boxes do not intersect unless one
// stands on the other (touching within a millimetre).
void expectNoInterpenetration(const Scenario& s) {
  for (std::size_t i = 0; i < s.objects.size(); ++i)
    for (std::size_t j = i + 1; j < s.objects.size(); ++j) {
      const Placed a = placed(s, s.objects[i], 0.0), b = placed(s, s.objects[j], 0.0);
      const bool stacked =
          std::abs(a.bottom() - b.top()) < 0.003 || std::abs(b.bottom() - a.top()) < 0.003;
      if (stacked) continue;
      const Eigen::Vector3d d = b.T.translation() - a.T.translation();
      const double reach = a.box.sizes().head<2>().norm() / 2 + b.box.sizes().head<2>().norm() / 2;
      if (d.head<2>().norm() > reach) continue;
      // Closer than their circumscribed circles: check the corners of one against the other.
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner =
            b.T * b.box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)).cast<double>();
        EXPECT_FALSE(a.contains(corner, -0.002)) << s.objects[i].id << " and " << s.objects[j].id;
      }
    }
}

TEST_F(ScenarioGeneratorTest, GeneratedScenariosLoadAndTheirGroundTruthIsConsistent) {
  std::set<std::string> kinds;
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scenario s = load(seed);
    expectConsistent(s);
    expectNoInterpenetration(s);
    const GeneratedScenario g = generateScenario({}, *shapes_, seed, "t");
    kinds.insert(g.kinds.begin(), g.kinds.end());
    EXPECT_LE(g.odometry_error.head<2>().norm(), 0.4);
    EXPECT_LE(std::abs(g.odometry_error.z()), 8.0 * M_PI / 180.0);
    EXPECT_GE(g.noise_factor, 1.0);
    EXPECT_LE(g.noise_factor, 3.0);
  }
  for (const char* kind : {"approach", "carry", "container_in", "occlusion"})
    EXPECT_TRUE(kinds.count(kind)) << kind << " never generated in 10 seeds";
}

}  // namespace
}  // namespace sgt::sim
