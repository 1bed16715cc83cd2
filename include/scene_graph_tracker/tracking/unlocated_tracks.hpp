#pragma once
// Established tracks seen missing where they stood. Evidence of absence says the object is not
// there, not that it is gone: a carried object leaves its track behind, and comes back elsewhere.
// Such a track leaves the scene (no pose is known), and its id waits for the next detection of its
// class that no track takes, which starts a tentative track under that id instead of a new one.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace sgt {

class UnlocatedTracks {
 public:
  // Track `id` of `class_name`, last at `where` (map frame), seen missing at `stamp`.
  void add(const std::string& id, const std::string& class_name, const Eigen::Vector3d& where,
           double stamp);
  // The unclaimed id of `class_name` whose track was last nearest `where`, now claimed by the
  // track it starts; empty when there is none.
  std::string claim(const std::string& class_name, const Eigen::Vector3d& where);
  // The track that claimed `id` was confirmed: the object is found, the id is no longer waiting.
  void found(const std::string& id);
  // The track that claimed `id` went before it was confirmed: the id waits again.
  void release(const std::string& id);
  // Forgets the ids that have waited longer than keep_s by `stamp`.
  void expire(double stamp, double keep_s);
  void clear() { entries_.clear(); }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::string id, class_name;
    Eigen::Vector3d where;
    double since;
    bool claimed;
  };
  std::vector<Entry> entries_;
};

}  // namespace sgt
