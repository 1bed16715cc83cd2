// Object catalog from YAML: meshes, symmetries, errors that name the class and line; the same
// catalog pointed at the paper's meshes.
#include <gtest/gtest.h>

#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "support.hpp"

namespace sgt {
namespace {

const std::string kCatalog = std::string(SGT_SOURCE_DIR) + "/config/objects.yaml";

TEST(ObjectCatalog, LoadsThePackageCatalog) {
  const ObjectCatalog catalog = loadObjectCatalog(kCatalog);
  EXPECT_EQ(catalog.names(),
            (std::vector<std::string>{"klt", "materialbox", "multimeter", "relay", "screwdriver"}));
  // The file's order: the class ids of a detector trained on this catalog.
  EXPECT_EQ(catalog.listed(),
            (std::vector<std::string>{"multimeter", "screwdriver", "materialbox", "klt", "relay"}));
  const ObjectClass& mm = catalog.get("multimeter");
  EXPECT_NEAR(mm.box.sizes().x(), 0.180, 0.002);
  EXPECT_NEAR(mm.box.sizes().y(), 0.087, 0.002);
  EXPECT_NEAR(mm.box.sizes().z(), 0.042, 0.002);
  EXPECT_FALSE(mm.symmetry.any());
  // Viewers get the configured URI, which resolves on any machine with the package.
  EXPECT_EQ(mm.mesh_uri, "package://scene_graph_tracker/meshes/multimeter.stl");
  EXPECT_EQ(mm.mesh_scale, 1.0f);
  EXPECT_GT(mm.diameter, 0.19);
  EXPECT_LT(mm.diameter, 0.21);
  const ObjectClass& sd = catalog.get("screwdriver");
  ASSERT_EQ(sd.symmetry.continuous.size(), 1u);
  EXPECT_TRUE(sd.symmetry.continuous[0].axis.isApprox(Eigen::Vector3d::UnitX()));
  const ObjectClass& klt = catalog.get("klt");
  ASSERT_EQ(klt.symmetry.discrete.size(), 1u);
  EXPECT_TRUE(klt.symmetry.discrete[0].linear().isApprox(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-12));
  EXPECT_THROW(catalog.get("hammer"), CatalogError);
}

TEST(ObjectCatalog, SampledSymmetries) {
  Symmetry s;
  EXPECT_EQ(s.sampled().size(), 1u);
  s.continuous.push_back({Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero()});
  const auto samples = s.sampled(M_PI / 2);
  ASSERT_EQ(samples.size(), 4u);
  // Each sample maps the axis onto itself.
  for (const auto& S : samples)
    EXPECT_TRUE((S * Eigen::Vector3d(0.1, 0, 0)).isApprox(Eigen::Vector3d(0.1, 0, 0)));
}

TEST(ObjectCatalog, BoxHalfTurnsMapAnOffCentreBoxOntoItself) {
  const Eigen::AlignedBox3f box(Eigen::Vector3f(0.0f, -0.1f, 0.2f),
                                Eigen::Vector3f(0.4f, 0.1f, 0.3f));
  const auto turns = boxHalfTurns(box);
  EXPECT_TRUE(turns[0].isApprox(Eigen::Isometry3d::Identity()));
  for (std::size_t k = 1; k < turns.size(); ++k) {
    EXPECT_NEAR(Eigen::AngleAxisd(turns[k].linear()).angle(), M_PI, 1e-12) << k;
    for (int c = 0; c < 8; ++c) {  // each corner onto a corner
      const Eigen::Vector3d p =
          turns[k] * box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)).cast<double>();
      double nearest = 1.0;
      for (int d = 0; d < 8; ++d)
        nearest = std::min(
            nearest,
            (p - box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(d)).cast<double>())
                .norm());
      EXPECT_LT(nearest, 1e-6) << k << " " << c;
    }
  }
}

TEST(ObjectCatalog, ErrorsNameTheClassAndLine) {
  const std::string path =
      test::writeFile("bad_catalog.yaml", "objects:\n  relay:\n    scale: 1.0\n");
  try {
    loadObjectCatalog(path);
    FAIL() << "no error";
  } catch (const CatalogError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("relay"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mesh"), std::string::npos) << msg;
    EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
  }
  const std::string missing =
      test::writeFile("missing_mesh.yaml", "objects:\n  relay:\n    mesh: nowhere.stl\n");
  try {
    loadObjectCatalog(missing);
    FAIL() << "no error";
  } catch (const CatalogError& e) {
    EXPECT_NE(std::string(e.what()).find("nowhere.stl"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadObjectCatalog(test::writeFile("no_objects.yaml", "classes: []\n")),
               CatalogError);
  EXPECT_THROW(loadObjectCatalog(test::writeFile("broken.yaml", "objects: [\n")), CatalogError);
}

// Each `bad` line in a class's entry is a CatalogError naming `key` and the class.
void expectErrorsNaming(const std::string& key, std::initializer_list<const char*> bad_lines) {
  const std::string mesh = "package://scene_graph_tracker/meshes/multimeter.stl";
  for (const char* bad : bad_lines) {
    const std::string path = test::writeFile(
        "bad_" + key + ".yaml", "objects:\n  mm:\n    mesh: " + mesh + "\n    " + bad + "\n");
    try {
      loadObjectCatalog(path);
      FAIL() << "no error for " << bad;
    } catch (const CatalogError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("class 'mm'"), std::string::npos) << e.what();
    }
  }
}

// A mesh modelled in other axes than its poses refer to (a Y-up OBJ): `origin` puts it into the
// object frame as a URDF visual's origin does, before anything uses it.
TEST(ObjectCatalog, OriginMovesTheMeshIntoTheObjectFrame) {
  const std::string mesh = "package://scene_graph_tracker/meshes/multimeter.stl";
  const ObjectClass plain =
      loadObjectCatalog(test::writeFile("plain.yaml", "objects:\n  mm:\n    mesh: " + mesh + "\n"))
          .get("mm");
  const ObjectClass moved =
      loadObjectCatalog(test::writeFile("origin.yaml", "objects:\n  mm:\n    mesh: " + mesh +
                                                           "\n    origin: {xyz: [0.1, 0, 0], "
                                                           "rpy: [1.5707963267948966, 0, 0]}\n"))
          .get("mm");
  const Eigen::Isometry3d T(Eigen::Translation3d(0.1, 0, 0) *
                            Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(moved.T_object_mesh.isApprox(T, 1e-12));
  // Rotated about x by 90 deg: the box's y and z sizes swap, its centre moves with the origin.
  EXPECT_NEAR(moved.box.sizes().y(), plain.box.sizes().z(), 1e-5);
  EXPECT_NEAR(moved.box.sizes().z(), plain.box.sizes().y(), 1e-5);
  const Eigen::Vector3d centre = T * plain.box.center().cast<double>();
  EXPECT_TRUE(moved.box.center().cast<double>().isApprox(centre, 1e-5))
      << moved.box.center().transpose() << " vs " << centre.transpose();
  EXPECT_NEAR(moved.diameter, plain.diameter, 1e-6);
  ASSERT_EQ(moved.mesh->vertices.size(), plain.mesh->vertices.size());
  EXPECT_TRUE(moved.mesh->vertices[7].cast<double>().isApprox(
      T * plain.mesh->vertices[7].cast<double>(), 1e-6));
  expectErrorsNaming("origin",
                     {"origin: 5", "origin: {rpy: [1, 2]}", "origin: {xyz: [0, .nan, 0]}"});
}

// A class's main colour, for training renders: read where given, absent otherwise, refused out of
// 0..1 or not three numbers.
TEST(ObjectCatalog, ColourIsOptionalAndChecked) {
  const std::string mesh = "package://scene_graph_tracker/meshes/multimeter.stl";
  const ObjectCatalog catalog = loadObjectCatalog(test::writeFile(
      "colour.yaml", "objects:\n  a:\n    mesh: " + mesh + "\n    colour: [0.9, 0.7, 0.25]\n" +
                         "  b:\n    mesh: " + mesh + "\n"));
  ASSERT_TRUE(catalog.get("a").colour.has_value());
  EXPECT_TRUE(catalog.get("a").colour->isApprox(Eigen::Vector3f(0.9f, 0.7f, 0.25f)));
  EXPECT_FALSE(catalog.get("b").colour.has_value());
  expectErrorsNaming("colour", {"colour: 5", "colour: [1, 0]", "colour: [0.5, 1.5, 0]",
                                "colour: [0, .nan, 0]", "colour: [0, -0.1, 0]"});
}

// make fuzz (config): YAML type errors and unresolvable paths escaped as YAML::Exception or
// MeshError; every problem is a CatalogError naming the file and the class.
TEST(ObjectCatalog, AnythingWrongIsACatalogErrorNamingTheClass) {
  for (const char* text :
       {"objects:\n  relay:\n    mesh: [a.stl, b.stl]\n",
        "objects:\n  relay:\n    mesh: package://no_such_package/relay.stl\n",
        "objects:\n  relay: 5\n", "objects:\n  relay:\n    mesh: relay.stl\n    scale: [1]\n"}) {
    const std::string path = test::writeFile("odd_catalog.yaml", text);
    try {
      loadObjectCatalog(path);
      FAIL() << "no error for " << text;
    } catch (const CatalogError& e) {
      EXPECT_NE(std::string(e.what()).find("class 'relay'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(loadObjectCatalog(test::writeFile("list.yaml", "- objects\n- relay\n")),
               CatalogError);
  EXPECT_THROW(loadObjectCatalog(test::writeFile("dir.yaml", "mesh_dir: [1]\nobjects: {}\n")),
               CatalogError);
}

TEST(ObjectCatalog, PointsAtThePaperMeshes) {
  SGT_REQUIRE_PBR_OBJECTS(dir);
  const ObjectCatalog catalog = loadObjectCatalog(kCatalog, dir + "/meshes");
  EXPECT_NE(catalog.get("klt").mesh_path.find("klt3147.stl"), std::string::npos);
  EXPECT_EQ(catalog.get("klt").mesh_uri, "file://" + catalog.get("klt").mesh_path);
  // The CAD file has 33,446 triangles, two of them zero-area (dropped at load).
  EXPECT_EQ(catalog.get("multimeter").mesh->triangleCount(), 33444u);
  // Symmetries come from model_info.json.
  EXPECT_EQ(catalog.get("klt").symmetry.discrete.size(), 1u);
  EXPECT_EQ(catalog.get("screwdriver").symmetry.continuous.size(), 1u);
  EXPECT_FALSE(catalog.get("relay").symmetry.any());
}

}  // namespace
}  // namespace sgt
