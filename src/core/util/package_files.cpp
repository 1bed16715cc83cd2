#include "scene_graph_tracker/util/package_files.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace sgt {
namespace {

const char* const kPackage = "scene_graph_tracker";

bool isPackageDir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "package.xml", ec);
}

// The share directory beside this library: <prefix>/lib/lib*.so -> <prefix>/share/<package>.
fs::path besideLibrary() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&packageShareDir), &info) == 0 || !info.dli_fname)
    return {};
  std::error_code ec;
  const fs::path lib = fs::canonical(info.dli_fname, ec);
  if (ec) return {};
  return lib.parent_path().parent_path() / "share" / kPackage;
}

std::string inRosPackagePath(const std::string& package) {
  const char* rpp = std::getenv("ROS_PACKAGE_PATH");
  if (!rpp) return "";
  std::stringstream entries(rpp);
  std::string entry;
  while (std::getline(entries, entry, ':')) {
    if (entry.empty()) continue;
    const fs::path dir(entry);
    if (dir.filename() == package && isPackageDir(dir)) return dir.string();
    if (isPackageDir(dir / package)) return (dir / package).string();
  }
  return "";
}

}  // namespace

std::string packageShareDir() {
  if (const char* env = std::getenv("SGT_SHARE_DIR"); env && *env) {
    if (isPackageDir(env)) return env;
    throw PackageFileError(std::string("SGT_SHARE_DIR='") + env + "' holds no package.xml");
  }
  const fs::path beside = besideLibrary();
  if (!beside.empty() && isPackageDir(beside)) return beside.string();
  const std::string ros = inRosPackagePath(kPackage);
  if (!ros.empty()) return ros;
  throw PackageFileError(std::string("cannot find the ") + kPackage +
                         " share directory: SGT_SHARE_DIR is unset, '" + beside.string() +
                         "' holds no package.xml and ROS_PACKAGE_PATH has no " + kPackage +
                         " (source the workspace's setup.bash)");
}

std::string packageFile(const std::string& relative) {
  return (fs::path(packageShareDir()) / relative).string();
}

std::string findPackageDir(const std::string& package) {
  if (package == kPackage) return packageShareDir();
  return inRosPackagePath(package);
}

}  // namespace sgt
