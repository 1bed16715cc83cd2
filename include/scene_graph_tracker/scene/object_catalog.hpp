// The object catalog: which classes the tracker knows, their meshes and symmetries.
// Loaded from YAML (config/objects.yaml); symmetries as in BOP's model_info.json.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene_graph_tracker/geometry/triangle_mesh.hpp"

namespace sgt {

class CatalogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ContinuousSymmetry {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // unit, object frame
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // a point on the axis
};

struct Symmetry {
  std::vector<Eigen::Isometry3d> discrete;  // without the identity
  std::vector<ContinuousSymmetry> continuous;
  bool any() const { return !discrete.empty() || !continuous.empty(); }
  // Symmetry transforms S (T_true * S looks the same as T_true), identity first; continuous
  // symmetries are sampled every `continuous_step_rad`. Used by symmetry-aware errors.
  std::vector<Eigen::Isometry3d> sampled(double continuous_step_rad = M_PI / 36.0) const;
};

// The smallest angle (rad) between rotation a and b * S over `symmetries` (Symmetry::sampled(),
// identity first): how far apart two orientations of a symmetric object are.
double angleUpToSymmetries(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b,
                           const std::vector<Eigen::Isometry3d>& symmetries);

// The identity and the half turns about the x, y and z axes through the box's centre: the turns
// that map the box onto itself (object frame: an object at T looks like its box at T * turn).
std::array<Eigen::Isometry3d, 4> boxHalfTurns(const Eigen::AlignedBox3f& box);

struct ObjectClass {
  std::string name;
  std::string mesh_path;  // resolved file path
  // The mesh for viewers on other machines (rviz markers): the configured package:// URI, else
  // file://<mesh_path>; drawn at `mesh_scale` (the catalog's `scale`).
  std::string mesh_uri;
  float mesh_scale = 1.0f;
  // The mesh file's pose in the object frame (the catalog's `origin`), for a mesh modelled in
  // other axes than its poses refer to (Y-up, or about another point). `mesh` is already moved by
  // it; a viewer drawing mesh_uri puts it at T_world_object * T_object_mesh.
  Eigen::Isometry3d T_object_mesh = Eigen::Isometry3d::Identity();
  std::shared_ptr<const TriangleMesh> mesh;  // in the object frame
  Symmetry symmetry;
  // The object's main colour (RGB 0..1, the catalog's `colour`), where it has one: renders for
  // training draw it in that colour (render_dataset). A class without one is drawn in random
  // colours.
  std::optional<Eigen::Vector3f> colour;
  Eigen::AlignedBox3f box;  // of the mesh, object frame
  double diameter = 0.0;
};

class ObjectCatalog {
 public:
  void add(ObjectClass object);
  bool contains(const std::string& name) const { return classes_.count(name) > 0; }
  const ObjectClass& get(const std::string& name) const;
  std::vector<std::string> names() const;  // sorted
  // The names in the order they were first added: a catalog file's order, which a detector
  // trained on the catalog uses as its class ids.
  const std::vector<std::string>& listed() const { return listed_; }
  std::size_t size() const { return classes_.size(); }

 private:
  std::map<std::string, ObjectClass> classes_;
  std::vector<std::string> listed_;
};

// Format:
//   mesh_dir: optional directory relative mesh paths are resolved against (default: the
//             YAML file's directory)
//   objects:
//     multimeter:
//       mesh: package://scene_graph_tracker/meshes/multimeter.stl   # path, file:// or package://
//       scale: 1.0                                                  # optional
//       origin: {xyz: [0, 0, 0], rpy: [1.5708, 0, 0]}  # optional: the mesh's pose in the object
//                                          # frame, as a URDF visual's (m; rad, fixed x, y, z)
//       symmetries_discrete: [[16 numbers, row-major 4x4], ...]      # optional
//       symmetries_continuous: [{axis: [1, 0, 0], offset: [0, 0, 0]}]  # optional
//       colour: [0.95, 0.78, 0.1]      # optional: main colour, RGB 0..1, for training renders
// Symmetries are in the object frame.
// `mesh_dir_override`, when not empty, replaces mesh_dir and makes every mesh be looked up by
// its file name in that directory or its sub-directory named after the class (so a catalog can
// point at another set of meshes, e.g. ../shared/data/pbr_objects/meshes).
// Throws CatalogError naming the file (and the class) for anything it cannot use: YAML syntax, a
// value of the wrong type, a path that does not resolve, a mesh that does not load.
ObjectCatalog loadObjectCatalog(const std::string& yaml_path,
                                const std::string& mesh_dir_override = "");

}  // namespace sgt
