#include "scene_graph_tracker/geometry/mesh_io.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "scene_graph_tracker/geometry/mesh_header.hpp"
#include "scene_graph_tracker/geometry/polygon_triangulation.hpp"
#include "scene_graph_tracker/util/package_files.hpp"

namespace fs = std::filesystem;

namespace sgt {
namespace {

[[noreturn]] void fail(const std::string& what, const std::string& problem) {
  throw MeshError("mesh '" + what + "': " + problem);
}

float triangleArea(const TriangleMesh& m, const Triangle& t) {
  return 0.5f *
         (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
}

bool isDegenerate(const TriangleMesh& m, const Triangle& t, float min_area) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(triangleArea(m, t) > min_area);
}

// Appends the triangles of one face: a triangle as it is, a polygon split by triangulatePolygon;
// points and lines carry no surface.
void addFace(const aiMesh* mesh, unsigned f, std::uint32_t offset, TriangleMesh& out,
             MeshLoadReport& report, const std::string& path) {
  const aiFace& face = mesh->mFaces[f];
  if (face.mNumIndices < 3) return;
  if (face.mNumIndices > kMaxPolygonCorners)
    fail(path, "face " + std::to_string(f) + " has " + std::to_string(face.mNumIndices) +
                   " corners, more than the " + std::to_string(kMaxPolygonCorners) + " accepted");
  std::vector<Eigen::Vector3f> corners;
  for (unsigned c = 0; c < face.mNumIndices; ++c) {
    if (face.mIndices[c] >= mesh->mNumVertices)
      fail(path, "face " + std::to_string(f) + " references vertex " +
                     std::to_string(face.mIndices[c]) + " of " +
                     std::to_string(mesh->mNumVertices));
    corners.push_back(out.vertices[offset + face.mIndices[c]]);
  }
  for (const auto& t : triangulatePolygon(corners))
    out.triangles.push_back(
        {face.mIndices[t[0]] + offset, face.mIndices[t[1]] + offset, face.mIndices[t[2]] + offset});
  if (face.mNumIndices > 3) ++report.triangulated_polygons;
}

void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, TriangleMesh& out,
             MeshLoadReport& report, const std::string& path) {
  const aiMatrix4x4 T = parent * node->mTransformation;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
    if (!(mesh->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
    const auto offset = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D v = T * mesh->mVertices[i];
      out.vertices.emplace_back(v.x, v.y, v.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) addFace(mesh, f, offset, out, report, path);
    ++report.merged_meshes;
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    collect(scene, node->mChildren[c], T, out, report, path);
}

}  // namespace

std::size_t removeDegenerateTriangles(TriangleMesh& mesh, float min_area) {
  const std::size_t before = mesh.triangles.size();
  mesh.triangles.erase(
      std::remove_if(mesh.triangles.begin(), mesh.triangles.end(),
                     [&](const Triangle& t) { return isDegenerate(mesh, t, min_area); }),
      mesh.triangles.end());
  return before - mesh.triangles.size();
}

void validateMesh(const TriangleMesh& mesh, const std::string& what) {
  if (mesh.vertices.empty() || mesh.triangles.empty()) fail(what, "has no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite())
      fail(what, "vertex " + std::to_string(i) + " is not finite (NaN or inf)");
  const auto n = mesh.vertices.size();
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Triangle& t = mesh.triangles[f];
    for (auto idx : t)
      if (idx >= n)
        fail(what, "triangle " + std::to_string(f) + " references vertex " + std::to_string(idx) +
                       " but the mesh has " + std::to_string(n) + " vertices");
    if (isDegenerate(mesh, t, 0.0f))
      fail(what, "triangle " + std::to_string(f) + " is degenerate (zero area)");
  }
}

TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options,
                      MeshLoadReport* report_out) {
  MeshLoadReport report;
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "file does not exist");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(path, "cannot read its size: " + ec.message());
  if (bytes == 0) fail(path, "file is empty");
  checkMeshHeader(path, bytes);
  if (!(options.scale > 0.0f) || !std::isfinite(options.scale))
    fail(path, "scale " + std::to_string(options.scale) + " must be a positive finite number");

  Assimp::Importer importer;
  // Keep COLLADA vertices as authored (URDF meshes are Z-up; assimp would rotate them to Y-up).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // No post-processing beyond validation: JoinIdenticalVertices/FindDegenerates would hide what
  // the file really holds, and assimp's Triangulate asserts (aborts the process) on face lists
  // that disagree with their header, so collect() triangulates polygons itself.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode)
    fail(path, std::string("assimp cannot read it: ") + importer.GetErrorString());
  TriangleMesh mesh;
  collect(scene, scene->mRootNode, aiMatrix4x4(), mesh, report, path);
  if (mesh.triangles.empty()) fail(path, "contains no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite())
      fail(path, "vertex " + std::to_string(i) + " is not finite (NaN or inf)");
  if (options.scale != 1.0f) mesh.scale(options.scale);

  if (options.drop_degenerate) {
    report.dropped_degenerate = removeDegenerateTriangles(mesh, 0.0f);
    if (mesh.triangles.empty()) fail(path, "all triangles are degenerate (zero area)");
  }
  validateMesh(mesh, path);
  if (options.max_extent_m > 0.0f) {
    const float extent = mesh.boundingBox().sizes().maxCoeff();
    if (extent > options.max_extent_m) {
      std::ostringstream msg;
      msg << "largest extent " << extent << " m exceeds the plausible " << options.max_extent_m
          << " m: wrong unit? (a mesh in millimetres needs scale 0.001)";
      fail(path, msg.str());
    }
  }
  if (report_out) *report_out = report;
  return mesh;
}

void saveStl(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw MeshError("cannot write '" + path + "'");
  char header[80] = "scene_graph_tracker binary STL";
  out.write(header, 80);
  const auto n = static_cast<std::uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    Eigen::Vector3f normal = (b - a).cross(c - a);
    if (normal.norm() > 0) normal.normalize();
    for (const Eigen::Vector3f& v : {normal, a, b, c})
      out.write(reinterpret_cast<const char*>(v.data()), 12);
    const std::uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

void savePly(const TriangleMesh& mesh, const std::string& path) {
  static_assert(sizeof(float) == 4 && sizeof(std::uint32_t) == 4, "PLY float and uint are 4 bytes");
  const std::uint16_t probe = 1;
  if (*reinterpret_cast<const std::uint8_t*>(&probe) != 1)
    throw MeshError("savePly: needs a little-endian host");
  std::ofstream out(path, std::ios::binary);
  if (!out) throw MeshError("cannot write '" + path + "'");
  out << "ply\nformat binary_little_endian 1.0\ncomment scene_graph_tracker\n"
      << "element vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size()
      << "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const Eigen::Vector3f& v : mesh.vertices)
    out.write(reinterpret_cast<const char*>(v.data()), 12);
  for (const Triangle& t : mesh.triangles) {
    const std::uint8_t n = 3;
    out.write(reinterpret_cast<const char*>(&n), 1);
    out.write(reinterpret_cast<const char*>(t.data()), 12);
  }
  if (!out) throw MeshError("cannot write '" + path + "'");
}

std::string resolveResourcePath(const std::string& uri, const std::string& base_dir) {
  const std::string pkg_prefix = "package://", file_prefix = "file://";
  if (uri.rfind(file_prefix, 0) == 0) return uri.substr(file_prefix.size());
  if (uri.rfind(pkg_prefix, 0) == 0) {
    const std::string rest = uri.substr(pkg_prefix.size());
    const auto slash = rest.find('/');
    const std::string pkg = rest.substr(0, slash);
    const std::string rel = slash == std::string::npos ? "" : rest.substr(slash + 1);
    std::string dir;
    try {
      dir = findPackageDir(pkg);
    } catch (const PackageFileError& e) {
      throw MeshError("cannot resolve '" + uri + "': " + e.what());
    }
    if (dir.empty())
      throw MeshError("cannot resolve '" + uri + "': package '" + pkg +
                      "' not found in ROS_PACKAGE_PATH");
    return (fs::path(dir) / rel).string();
  }
  fs::path p(uri);
  if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
  return p.string();
}

}  // namespace sgt
