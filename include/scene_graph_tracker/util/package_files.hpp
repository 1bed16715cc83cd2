#pragma once
// The package's data files (config, meshes, models, sql) and ROS packages' directories, found at
// run time: nothing is compiled in, so a devel space, an install space and a .deb all work.
#include <stdexcept>
#include <string>

namespace sgt {

struct PackageFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// scene_graph_tracker's share directory, the first of:
//  1. $SGT_SHARE_DIR;
//  2. <directory of libscene_graph_tracker_core>/../share/scene_graph_tracker, the data installed
//     with the library (the devel space links the source tree's data there);
//  3. the package in ROS_PACKAGE_PATH.
// Throws PackageFileError naming every place it looked.
std::string packageShareDir();

// packageShareDir() / relative.
std::string packageFile(const std::string& relative);

// A ROS package's directory through ROS_PACKAGE_PATH (each entry the package itself or a directory
// holding it, as rospack's first level); scene_graph_tracker through packageShareDir(). "" when not
// found.
std::string findPackageDir(const std::string& package);

}  // namespace sgt
