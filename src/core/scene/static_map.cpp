#include "scene_graph_tracker/scene/static_map.hpp"

#include <urdf_parser/urdf_parser.h>

#include <filesystem>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"

namespace sgt {
namespace {

Eigen::Isometry3f toEigen(const urdf::Pose& p) {
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  T.translate(Eigen::Vector3f(p.position.x, p.position.y, p.position.z));
  T.rotate(Eigen::Quaternionf(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized());
  return T;
}

TriangleMesh visualMesh(const urdf::Geometry& g, const std::string& urdf_path,
                        const std::string& link) {
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      return makeBox(Eigen::Vector3f(b.dim.x, b.dim.y, b.dim.z));
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      return makeCylinder(c.radius, c.length);
    }
    case urdf::Geometry::SPHERE:
      return makeSphere(static_cast<const urdf::Sphere&>(g).radius);
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      const std::string base = std::filesystem::path(urdf_path).parent_path().string();
      TriangleMesh mesh;
      try {
        mesh = loadMesh(resolveResourcePath(m.filename, base));
      } catch (const MeshError& e) {
        throw MeshError("URDF '" + urdf_path + "', link '" + link + "': " + e.what());
      }
      for (auto& v : mesh.vertices)
        v = v.cwiseProduct(Eigen::Vector3f(m.scale.x, m.scale.y, m.scale.z));
      return mesh;
    }
  }
  throw MeshError("URDF '" + urdf_path + "', link '" + link + "': unsupported geometry type");
}

void addLink(const urdf::Link& link, const Eigen::Isometry3f& T_map_link, const std::string& path,
             TriangleMesh& out) {
  for (const auto& visual : link.visual_array)
    if (visual && visual->geometry)
      out.append(visualMesh(*visual->geometry, path, link.name),
                 T_map_link * toEigen(visual->origin));
  if (link.visual_array.empty() && link.visual && link.visual->geometry)
    out.append(visualMesh(*link.visual->geometry, path, link.name),
               T_map_link * toEigen(link.visual->origin));
  for (const auto& joint : link.child_joints) {
    for (const auto& c : link.child_links)
      if (c->name == joint->child_link_name)
        addLink(*c, T_map_link * toEigen(joint->parent_to_joint_origin_transform), path, out);
  }
}

}  // namespace

TriangleMesh staticMapFromUrdf(const std::string& path) {
  if (!std::filesystem::exists(path)) throw MeshError("URDF '" + path + "': file does not exist");
  const auto model = urdf::parseURDFFile(path);
  if (!model) throw MeshError("URDF '" + path + "': urdfdom cannot parse it");
  const auto root = model->getRoot();
  if (!root) throw MeshError("URDF '" + path + "': has no root link");
  TriangleMesh out;
  addLink(*root, Eigen::Isometry3f::Identity(), path, out);
  validateMesh(out, path);
  return out;
}

TriangleMesh loadStaticMap(const std::string& path) {
  if (std::filesystem::path(path).extension() == ".urdf") return staticMapFromUrdf(path);
  return loadMesh(path);
}

}  // namespace sgt
