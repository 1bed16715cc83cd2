// Frames and settings shared by the SEMAP writer tests: a table and two boxes sliding over it.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "scene_graph_tracker/semap/writer.hpp"

namespace sgt::test {

inline std::shared_ptr<const semap::ClassShape> boxShape(const std::string& name, double half) {
  auto s = std::make_shared<semap::ClassShape>();
  s->name = name,
  s->box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-half), Eigen::Vector3d::Constant(half));
  return s;
}

// Frame i: a table and two objects sliding over it; 20 ms apart, three pose rows.
inline semap::Frame slidingFrame(int i) {
  static const auto table = boxShape("table", 0.4), box = boxShape("box", 0.05);
  semap::Frame f;
  f.stamp = 1000.0 + 0.02 * i;
  f.update_relations = i % 25 == 0;
  const double x = 0.3 * std::sin(0.05 * i);
  f.objects = {{"table_1", table, "map", Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.4))},
               {"box_1", box, "table_1", Eigen::Isometry3d(Eigen::Translation3d(x, 0, 0.851))},
               {"box_2", box, "table_1", Eigen::Isometry3d(Eigen::Translation3d(-x, 0.2, 0.851))}};
  return f;
}

inline semap::WriterOptions fastRetry(std::size_t queue_size) {
  semap::WriterOptions o;
  o.queue_size = queue_size, o.backoff_min_s = 0.05, o.backoff_max_s = 0.4;
  return o;
}

// The stamps stored for `id`, in the order the rows arrived.
inline std::vector<double> arrivedStamps(semap::SemapDb& db, const std::string& id) {
  std::vector<double> stamps;
  for (const auto& row :
       db.query("SELECT extract(epoch FROM stamp)::float8 FROM pose_history WHERE instance_id = '" +
                id + "' ORDER BY arrival"))
    stamps.push_back(std::stod(row[0]));
  return stamps;
}

}  // namespace sgt::test
