#include "scene_graph_tracker/ros/track_id_store.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace sgt::ros {

std::map<std::string, int> TrackIdStore::load() const {
  std::map<std::string, int> last;
  if (!enabled() || !std::filesystem::exists(path_)) return last;
  try {
    const YAML::Node root = YAML::LoadFile(path_);
    if (root.IsNull()) return last;
    if (!root.IsMap()) throw TrackIdStoreError("not a map of class names to numbers");
    for (const auto& kv : root) {
      const int n = kv.second.as<int>();
      if (n < 0)
        throw TrackIdStoreError("negative number for '" + kv.first.as<std::string>() + "'");
      last[kv.first.as<std::string>()] = n;
    }
  } catch (const YAML::Exception& e) {
    throw TrackIdStoreError("track id file " + path_ + ": " + e.what());
  } catch (const TrackIdStoreError& e) {
    throw TrackIdStoreError("track id file " + path_ + ": " + e.what());
  }
  return last;
}

void TrackIdStore::save(const std::map<std::string, int>& last) const {
  if (!enabled()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target(path_);
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const std::string tmp = path_ + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << "# scene_graph_tracker: the last track number of each class (ids are never reused)\n";
    for (const auto& [name, n] : last) out << YAML::Node(name) << ": " << n << "\n";
    out.flush();
    if (!out) throw TrackIdStoreError("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path_.c_str()) != 0)
    throw TrackIdStoreError("cannot replace " + path_ + " with " + tmp);
}

}  // namespace sgt::ros
