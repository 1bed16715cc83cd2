#include "scene_graph_tracker/scene/object_catalog.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "scene_graph_tracker/geometry/mesh_io.hpp"

namespace fs = std::filesystem;

namespace sgt {

double angleUpToSymmetries(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b,
                           const std::vector<Eigen::Isometry3d>& symmetries) {
  double best = M_PI;
  for (const Eigen::Isometry3d& S : symmetries)
    best = std::min(best, Eigen::AngleAxisd(a.transpose() * b * S.linear()).angle());
  return best;
}

std::array<Eigen::Isometry3d, 4> boxHalfTurns(const Eigen::AlignedBox3f& box) {
  const Eigen::Vector3d centre = box.center().cast<double>();
  std::array<Eigen::Isometry3d, 4> out;
  out.fill(Eigen::Isometry3d::Identity());
  for (int a = 0; a < 3; ++a) {
    out[a + 1].linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::Unit(a)).toRotationMatrix();
    out[a + 1].translation() = centre - out[a + 1].linear() * centre;
  }
  return out;
}

std::vector<Eigen::Isometry3d> Symmetry::sampled(double step) const {
  std::vector<Eigen::Isometry3d> base{Eigen::Isometry3d::Identity()};
  base.insert(base.end(), discrete.begin(), discrete.end());
  std::vector<Eigen::Isometry3d> out = base;
  for (const auto& c : continuous) {
    std::vector<Eigen::Isometry3d> next;
    const int n = std::max(1, static_cast<int>(std::round(2.0 * M_PI / step)));
    for (const auto& S : out)
      for (int k = 0; k < n; ++k) {
        Eigen::Isometry3d rot = Eigen::Isometry3d::Identity();
        rot.translate(c.offset);
        rot.rotate(Eigen::AngleAxisd(2.0 * M_PI * k / n, c.axis));
        rot.translate(-c.offset);
        next.push_back(S * rot);
      }
    out = std::move(next);
  }
  return out;
}

void ObjectCatalog::add(ObjectClass object) {
  const std::string name = object.name;
  if (!classes_.count(name)) listed_.push_back(name);
  classes_[name] = std::move(object);
}

const ObjectClass& ObjectCatalog::get(const std::string& name) const {
  const auto it = classes_.find(name);
  if (it == classes_.end()) throw CatalogError("object catalog: unknown class '" + name + "'");
  return it->second;
}

std::vector<std::string> ObjectCatalog::names() const {
  std::vector<std::string> out;
  for (const auto& kv : classes_) out.push_back(kv.first);
  return out;
}

namespace {

std::string where(const YAML::Node& n) {
  return n.Mark().line >= 0 ? " (line " + std::to_string(n.Mark().line + 1) + ")" : "";
}

Symmetry parseSymmetry(const YAML::Node& node, const std::string& ctx) {
  Symmetry sym;
  if (const auto d = node["symmetries_discrete"]) {
    for (const auto& m : d) {
      if (m.size() != 16)
        throw CatalogError(ctx + ": symmetries_discrete entries need 16 numbers" + where(m));
      Eigen::Matrix4d M;
      for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = m[i].as<double>();
      Eigen::Isometry3d T(M);
      // BOP stores translations in mm; our meshes are in metres.
      if (T.translation().norm() > 1.0) T.translation() *= 1e-3;
      sym.discrete.push_back(T);
    }
  }
  if (const auto c = node["symmetries_continuous"]) {
    for (const auto& s : c) {
      ContinuousSymmetry cs;
      const auto axis = s["axis"], offset = s["offset"];
      if (!axis || axis.size() != 3)
        throw CatalogError(ctx + ": continuous symmetry needs axis: [x, y, z]" + where(s));
      cs.axis = Eigen::Vector3d(axis[0].as<double>(), axis[1].as<double>(), axis[2].as<double>());
      if (!(cs.axis.norm() > 0))
        throw CatalogError(ctx + ": continuous symmetry axis is zero" + where(s));
      cs.axis.normalize();
      if (offset && offset.size() == 3)
        cs.offset = Eigen::Vector3d(offset[0].as<double>(), offset[1].as<double>(),
                                    offset[2].as<double>()) *
                    (offset[0].as<double>() > 1.0 ? 1e-3 : 1.0);
      sym.continuous.push_back(cs);
    }
  }
  return sym;
}

Eigen::Vector3d threeNumbers(const YAML::Node& n, const char* key, const std::string& ctx) {
  const YAML::Node v = n[key];
  if (!v) return Eigen::Vector3d::Zero();
  if (!v.IsSequence() || v.size() != 3)
    throw CatalogError(ctx + ": origin " + key + " needs three numbers" + where(v));
  const Eigen::Vector3d out(v[0].as<double>(), v[1].as<double>(), v[2].as<double>());
  if (!out.allFinite()) throw CatalogError(ctx + ": origin " + key + " is not finite" + where(v));
  return out;
}

// `origin: {xyz: [m], rpy: [rad]}` as a URDF visual's: rotation about the fixed x, then y, then z.
Eigen::Isometry3d parseOrigin(const YAML::Node& o, const std::string& ctx) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const YAML::Node origin = o["origin"];
  if (!origin) return T;
  if (!origin.IsMap())
    throw CatalogError(ctx + ": origin needs {xyz: [...], rpy: [...]}" + where(origin));
  const Eigen::Vector3d rpy = threeNumbers(origin, "rpy", ctx);
  T.translation() = threeNumbers(origin, "xyz", ctx);
  T.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

std::optional<Eigen::Vector3f> parseColour(const YAML::Node& o, const std::string& ctx) {
  const YAML::Node v = o["colour"];
  if (!v) return std::nullopt;
  if (!v.IsSequence() || v.size() != 3)
    throw CatalogError(ctx + ": colour needs three numbers [r, g, b] in 0..1" + where(v));
  const Eigen::Vector3f c(v[0].as<float>(), v[1].as<float>(), v[2].as<float>());
  if (!c.allFinite() || c.minCoeff() < 0.0f || c.maxCoeff() > 1.0f)
    throw CatalogError(ctx + ": colour needs three numbers [r, g, b] in 0..1" + where(v));
  return c;
}

std::string findInOverride(const fs::path& dir, const std::string& cls,
                           const std::string& configured) {
  const std::string file = fs::path(configured).filename().string();
  std::vector<fs::path> candidates{dir / file, dir / cls / file};
  for (const char* ext : {".stl", ".obj", ".ply", ".dae", ".glb", ".gltf"}) {
    candidates.push_back(dir / cls / (cls + ext));
    candidates.push_back(dir / (cls + ext));
  }
  for (const auto& c : candidates)
    if (fs::is_regular_file(c)) return c.string();
  if (fs::is_directory(dir / cls))
    for (const auto& e : fs::directory_iterator(dir / cls))
      if (e.path().extension() == ".stl" &&
          e.path().string().find("simplified") == std::string::npos)
        return e.path().string();
  throw CatalogError("object catalog: no mesh for class '" + cls + "' in " + dir.string());
}

}  // namespace

namespace {

ObjectClass loadClass(const std::string& cls, const YAML::Node& o, const std::string& ctx,
                      const std::string& mesh_dir, const std::string& mesh_dir_override) {
  if (!o.IsMap()) throw CatalogError(ctx + ": expected a map {mesh: ...}" + where(o));
  if (!o["mesh"]) throw CatalogError(ctx + ": missing 'mesh'" + where(o));
  const std::string configured = o["mesh"].as<std::string>();
  ObjectClass obj;
  obj.name = cls;
  obj.symmetry = parseSymmetry(o, ctx);
  obj.colour = parseColour(o, ctx);
  if (mesh_dir_override.empty()) {
    obj.mesh_path = resolveResourcePath(configured, mesh_dir);
  } else {
    obj.mesh_path = findInOverride(mesh_dir_override, cls, configured);
    const fs::path info = fs::path(mesh_dir_override) / cls / "model_info.json";
    if (fs::exists(info))
      obj.symmetry = parseSymmetry(YAML::LoadFile(info.string()), info.string());
  }
  const bool package_uri = mesh_dir_override.empty() && configured.rfind("package://", 0) == 0;
  obj.mesh_uri = package_uri ? configured : "file://" + obj.mesh_path;
  MeshLoadOptions opts;
  opts.scale = obj.mesh_scale = o["scale"] ? o["scale"].as<float>() : 1.0f;
  opts.max_extent_m = 5.0f;  // a tracked object larger than 5 m is a unit mistake
  auto mesh = std::make_shared<TriangleMesh>(loadMesh(obj.mesh_path, opts));
  obj.T_object_mesh = parseOrigin(o, ctx);
  mesh->transform(obj.T_object_mesh.cast<float>());
  obj.box = mesh->boundingBox();
  obj.diameter = mesh->diameter();
  obj.mesh = std::move(mesh);
  return obj;
}

}  // namespace

ObjectCatalog loadObjectCatalog(const std::string& yaml_uri, const std::string& mesh_dir_override) {
  const std::string file = "object catalog '" + yaml_uri + "'";
  std::string yaml_path;
  YAML::Node root;
  try {
    yaml_path = resolveResourcePath(yaml_uri);
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw CatalogError(file + ": " + e.what());
  } catch (const MeshError& e) {
    throw CatalogError(file + ": " + e.what());
  }
  const fs::path yaml_dir = fs::path(yaml_path).parent_path();
  // Whatever the file holds, what goes wrong is a CatalogError naming the file (and the class):
  // a value of the wrong YAML type, a path that does not resolve, a mesh that does not load.
  std::string ctx = file;
  try {
    if (!root.IsMap() || !root["objects"] || !root["objects"].IsMap())
      throw CatalogError(file + ": needs a map 'objects: {class: {mesh: ...}}'");
    std::string mesh_dir = yaml_dir.string();
    if (root["mesh_dir"])
      mesh_dir = resolveResourcePath(root["mesh_dir"].as<std::string>(), yaml_dir.string());
    ObjectCatalog catalog;
    for (const auto& kv : root["objects"]) {
      ctx = file;
      const std::string cls = kv.first.as<std::string>();
      ctx = file + ", class '" + cls + "'";
      catalog.add(loadClass(cls, kv.second, ctx, mesh_dir, mesh_dir_override));
    }
    return catalog;
  } catch (const YAML::Exception& e) {
    throw CatalogError(ctx + ": " + e.what());
  } catch (const MeshError& e) {
    throw CatalogError(ctx + ": " + e.what());
  } catch (const fs::filesystem_error& e) {
    throw CatalogError(ctx + ": " + e.what());
  }
}

}  // namespace sgt
