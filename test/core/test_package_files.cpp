// The package's data found at run time (util/package_files.hpp): beside the library in the devel
// space, through SGT_SHARE_DIR, and other packages through ROS_PACKAGE_PATH.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include "scene_graph_tracker/detection/keypoint_detector.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/util/package_files.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace sgt;

namespace {

// Sets an environment variable for one test and restores it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::optional<std::string>& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      setenv(name, value->c_str(), 1);
    else
      unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST(PackageFiles, FindsTheShareDirectoryBesideTheLibraryWithoutRosEnvironment) {
  ScopedEnv share("SGT_SHARE_DIR", std::nullopt), rpp("ROS_PACKAGE_PATH", std::nullopt);
  const fs::path dir = packageShareDir();
  EXPECT_TRUE(fs::exists(dir / "package.xml")) << dir;
  EXPECT_TRUE(fs::exists(packageFile("config/objects.yaml")));
  EXPECT_TRUE(fs::exists(packageFile("sql/semap_schema.sql")));
  // The data beside the library is this source tree's (the devel space links it).
  EXPECT_EQ(fs::canonical(dir / "config"), fs::canonical(fs::path(SGT_SOURCE_DIR) / "config"));
}

TEST(PackageFiles, ShippedDefaultsResolveAsPackageUris) {
  ScopedEnv rpp("ROS_PACKAGE_PATH", std::nullopt);
  const params::TrackerParameters tracker;
  const params::DetectorParameters detector;
  EXPECT_EQ(tracker.node.catalog.rfind("package://scene_graph_tracker/", 0), 0u);
  EXPECT_GT(loadObjectCatalog(tracker.node.catalog).size(), 0u);
  EXPECT_GT(detection::loadModelInfo(detector.model).keypoints, 0);
  params::TrackerParameters applied;
  EXPECT_NO_THROW(params::applyYamlFile(params::trackerSchema(), applied,
                                        "package://scene_graph_tracker/config/tracker.yaml"));
}

TEST(PackageFiles, ShareDirOverrideMustHoldAPackage) {
  const std::string dir = test::tempDir() + "/share_override";
  fs::create_directories(dir);
  {
    ScopedEnv share("SGT_SHARE_DIR", dir);
    EXPECT_THROW(packageShareDir(), PackageFileError);
    EXPECT_THROW(resolveResourcePath("package://scene_graph_tracker/x.stl"), MeshError);
    EXPECT_THROW(loadObjectCatalog("package://scene_graph_tracker/config/objects.yaml"),
                 CatalogError);
    std::ofstream(dir + "/package.xml") << "<package><name>scene_graph_tracker</name></package>\n";
    EXPECT_EQ(packageShareDir(), dir);
    EXPECT_EQ(resolveResourcePath("package://scene_graph_tracker/meshes/a.stl"),
              dir + "/meshes/a.stl");
  }
  EXPECT_NE(packageShareDir(), dir);
}

TEST(PackageFiles, OtherPackagesComeFromRosPackagePath) {
  const std::string dir = test::tempDir() + "/ws";
  fs::create_directories(dir + "/my_robot_description");
  std::ofstream(dir + "/my_robot_description/package.xml") << "<package/>\n";
  ScopedEnv rpp("ROS_PACKAGE_PATH", "/nonexistent:" + dir);
  EXPECT_EQ(findPackageDir("my_robot_description"), dir + "/my_robot_description");
  EXPECT_EQ(resolveResourcePath("package://my_robot_description/meshes/base.stl"),
            dir + "/my_robot_description/meshes/base.stl");
  EXPECT_EQ(findPackageDir("no_such_package_xyz"), "");
}
