// The last track number of each class, kept in a small YAML file ({klt: 3, relay: 5}) so that a
// restarted tracker never hands out an id again: the next KLT after a restart is klt_4, not a
// second klt_1 whose history a database (semap_bridge) would merge with the first one's.
#pragma once

#include <map>
#include <stdexcept>
#include <string>

namespace sgt::ros {

struct TrackIdStoreError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class TrackIdStore {
 public:
  explicit TrackIdStore(std::string path) : path_(std::move(path)) {}
  bool enabled() const { return !path_.empty(); }
  const std::string& path() const { return path_; }
  // The numbers in the file; empty when it does not exist yet. Throws TrackIdStoreError when it
  // cannot be read or is not a map of class names to non-negative numbers.
  std::map<std::string, int> load() const;
  // Writes the numbers (a temporary file renamed over the old one: a crash leaves either the old or
  // the new file, never half of one). Creates the directory. Throws TrackIdStoreError.
  void save(const std::map<std::string, int>& last) const;

 private:
  std::string path_;
};

}  // namespace sgt::ros
