#include "scene_graph_tracker/relations/furniture.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace sgt::relations {
namespace {

std::string where(const YAML::Node& n) {
  return n.Mark().line >= 0 ? " (line " + std::to_string(n.Mark().line + 1) + ")" : "";
}

template <int N>
Eigen::Matrix<double, N, 1> numbers(const YAML::Node& n, const std::string& ctx) {
  if (!n.IsSequence() || n.size() != N)
    throw FurnitureError(ctx + ": expected " + std::to_string(N) + " numbers" + where(n));
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) {
    try {
      v[i] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      throw FurnitureError(ctx + ": expected a number" + where(n[i]));
    }
    if (!std::isfinite(v[i])) throw FurnitureError(ctx + ": not a finite number" + where(n[i]));
  }
  return v;
}

template <typename Vector>
std::string list(const Vector& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (int i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

}  // namespace

std::vector<Entity> loadFurniture(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw FurnitureError("furniture '" + path + "': " + e.what());
  }
  const YAML::Node pieces = root.IsMap() ? root["furniture"] : YAML::Node();
  if (!pieces || !(pieces.IsSequence() || pieces.IsNull()))
    throw FurnitureError("furniture '" + path +
                         "': needs a list 'furniture: [{name, position, size}, ...]'");
  std::vector<Entity> out;
  std::set<std::string> names;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const YAML::Node& f = pieces[k];
    const std::string ctx = "furniture '" + path + "': entry " + std::to_string(k);
    if (!f.IsMap())
      throw FurnitureError(ctx + ": expected a map {name, position, size}" + where(f));
    for (const auto& kv : f) {
      const std::string key = kv.first.as<std::string>();
      if (key != "name" && key != "position" && key != "orientation" && key != "size")
        throw FurnitureError(ctx + ": unknown key '" + key + "'" + where(kv.first));
    }
    for (const char* key : {"name", "position", "size"})
      if (!f[key]) throw FurnitureError(ctx + ": missing '" + key + "'" + where(f));
    Entity e;
    e.name = f["name"].as<std::string>();
    if (e.name.empty()) throw FurnitureError(ctx + ": empty name" + where(f["name"]));
    if (!names.insert(e.name).second)
      throw FurnitureError(ctx + ": name '" + e.name + "' used twice" + where(f));
    e.movable = false;
    e.box.T_world_box.translation() = numbers<3>(f["position"], ctx + ".position");
    if (f["orientation"]) {
      const Eigen::Vector4d q = numbers<4>(f["orientation"], ctx + ".orientation");
      if (!(q.norm() > 0))
        throw FurnitureError(ctx + ".orientation: zero quaternion" + where(f["orientation"]));
      e.box.T_world_box.linear() =
          Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
    }
    const Eigen::Vector3d size = numbers<3>(f["size"], ctx + ".size");
    if (!(size.minCoeff() > 0))
      throw FurnitureError(ctx + ".size: edge lengths must be positive" + where(f["size"]));
    e.box.half_extents = size / 2;
    out.push_back(std::move(e));
  }
  return out;
}

void saveFurniture(const std::vector<Entity>& furniture, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw FurnitureError("furniture '" + path + "': cannot write it");
  out << "# Furniture of the static map (format: "
         "include/scene_graph_tracker/relations/furniture.hpp).\n"
      << "furniture:" << (furniture.empty() ? " []" : "") << "\n";
  for (const Entity& e : furniture) {
    const Eigen::Quaterniond q(e.box.T_world_box.linear());
    out << "  - name: " << YAML::Node(e.name) << "\n"
        << "    position: " << list(Eigen::Vector3d(e.box.T_world_box.translation())) << "\n"
        << "    orientation: " << list(Eigen::Vector4d(q.x(), q.y(), q.z(), q.w())) << "\n"
        << "    size: " << list(Eigen::Vector3d(2 * e.box.half_extents)) << "\n";
  }
  if (!out) throw FurnitureError("furniture '" + path + "': cannot write it");
}

}  // namespace sgt::relations
