// Mesh loading through assimp: formats, validation of broken files, mesh measures, sampling.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <functional>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "support.hpp"

namespace sgt {
namespace {

using test::writeFile;

// A right tetrahedron with unit legs: 4 vertices, 4 outward triangles.
const char* kTetObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

std::string tetStl() {
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string s = "solid tet\n";
  for (const auto& t : f) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int c : t)
      s += "vertex " + std::to_string(v[c][0]) + " " + std::to_string(v[c][1]) + " " +
           std::to_string(v[c][2]) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid tet\n";
}

const char* kTetPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

const char* kTetDae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="tet" name="tet"><mesh>
    <source id="pos"><float_array id="pos-array" count="12">0 0 0 1 0 0 0 1 0 0 0 1</float_array>
      <technique_common><accessor source="#pos-array" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="4"><input semantic="VERTEX" source="#verts" offset="0"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene"><node id="n"><instance_geometry url="#tet"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned n =
        (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    for (int s : {18, 12, 6, 0}) out += t[(n >> s) & 63];
  }
  if (i < in.size()) {
    unsigned n = (unsigned char)in[i] << 16;
    if (i + 1 < in.size()) n |= (unsigned char)in[i + 1] << 8;
    out += t[(n >> 18) & 63];
    out += t[(n >> 12) & 63];
    out += i + 1 < in.size() ? t[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string tetGltf() {
  const float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::uint16_t f[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  std::string bytes(reinterpret_cast<const char*>(v), sizeof(v));
  bytes.append(reinterpret_cast<const char*>(f), sizeof(f));
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
"buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,)" +
         base64(bytes) + R"("}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":24}],
"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]},
{"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"}]})";
}

class MeshFormats : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(MeshFormats, LoadsTheTetrahedron) {
  const auto& [name, text] = GetParam();
  const TriangleMesh mesh = loadMesh(writeFile(name, text));
  EXPECT_EQ(mesh.triangleCount(), 4u) << name;
  const auto box = mesh.boundingBox();
  EXPECT_TRUE(box.min().isApprox(Eigen::Vector3f::Zero(), 1e-6f))
      << name << " " << box.min().transpose();
  EXPECT_TRUE(box.max().isApprox(Eigen::Vector3f::Ones(), 1e-6f))
      << name << " " << box.max().transpose();
  EXPECT_NEAR(mesh.diameter(), std::sqrt(2.0), 1e-6) << name;
  EXPECT_NEAR(mesh.surfaceArea(), 1.5 + std::sqrt(3.0) / 2.0, 1e-5) << name;
}

INSTANTIATE_TEST_SUITE_P(Assimp, MeshFormats,
                         ::testing::Values(std::make_pair("tet.obj", std::string(kTetObj)),
                                           std::make_pair("tet.stl", tetStl()),
                                           std::make_pair("tet.ply", std::string(kTetPly)),
                                           std::make_pair("tet.dae", std::string(kTetDae)),
                                           std::make_pair("tet.gltf", tetGltf())),
                         [](const auto& info) {
                           std::string n = info.param.first;
                           n[n.find('.')] = '_';
                           return n;
                         });

void expectError(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no MeshError thrown";
  } catch (const MeshError& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

TEST(MeshValidation, MissingFile) {
  expectError([] { loadMesh("/nonexistent/part.stl"); },
              {"/nonexistent/part.stl", "does not exist"});
}

TEST(MeshValidation, EmptyFile) {
  const auto path = writeFile("empty.stl", "");
  expectError([&] { loadMesh(path); }, {path, "empty"});
}

TEST(MeshValidation, NoTriangles) {
  const auto path = writeFile("points.obj", "v 0 0 0\nv 1 0 0\n");
  expectError([&] { loadMesh(path); }, {path});
}

TEST(MeshValidation, NonFiniteVertex) {
  const auto path = writeFile(
      "nan.ply", std::string(kTetPly).replace(std::string(kTetPly).find("1 0 0\n"), 5, "nan 0 0"));
  expectError([&] { loadMesh(path); }, {path, "not finite"});
}

TEST(MeshValidation, DegenerateFacesAreDroppedOrRejected) {
  // Two good triangles plus one with a repeated index and one collinear.
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n2 0 0\n1 1 0\n3 0 1 2\n3 1 4 2\n3 0 0 1\n3 0 1 3\n";
  const auto path = writeFile("degenerate.ply", ply);
  MeshLoadReport report;
  const TriangleMesh mesh = loadMesh(path, {}, &report);
  EXPECT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(report.dropped_degenerate, 2u);
  MeshLoadOptions strict;
  strict.drop_degenerate = false;
  expectError([&] { loadMesh(path, strict); }, {path, "degenerate"});
}

TEST(MeshValidation, OutOfRangeFaceInMemory) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 7}};
  expectError([&] { validateMesh(mesh, "in-memory part"); },
              {"in-memory part", "vertex 7", "3 vertices"});
}

TEST(MeshValidation, OutOfRangeFaceInFile) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 "
      "0 1 9\n";
  const auto path = writeFile("range.ply", ply);
  expectError([&] { loadMesh(path); }, {path});
}

// make fuzz (mesh): assimp's triangulation asserted (abort) on an OFF file with fewer faces than
// its header says; assimp's validation refuses it first now.
TEST(MeshValidation, FewerFacesThanTheHeaderSays) {
  const auto path = writeFile("short.off",
                              "OFF\n4 4 6\n0 0 0\n0.1 0 0\n0 0.1 0\n0 0 0.1\n"
                              "3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expectError([&] { loadMesh(path); }, {path});
}

// make fuzz (mesh): assimp allocated 61 GB for an OFF header declaring 10^100 faces. A header that
// declares more vertices and faces than its file has bytes is refused before the import.
TEST(MeshValidation, HeaderCountsBeyondTheFileSize) {
  const auto off =
      writeFile("huge.off", "OFF\n3 1000000000000 0\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n");
  expectError([&] { loadMesh(off); }, {off, "declares 1e+12", "bytes"});
  const auto glued =
      writeFile("glued.off", "OFF3 1000000000000 0\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n");
  expectError([&] { loadMesh(glued); }, {glued, "declares", "bytes"});
  const auto ply = writeFile(
      "huge.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
      "float z\nelement face 99999999999\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { loadMesh(ply); }, {ply, "declares", "bytes"});
  // make fuzz (mesh): a broken PLY header made assimp's parser read past its buffer (SEGV); the
  // header is checked against the format's grammar first.
  const auto broken = writeFile(
      "broken.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
      "float z\nelement face 1\nproperty listusemtl uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { loadMesh(broken); }, {broken, "PLY header", "listusemtl"});
  const auto magic =
      writeFile("magic.ply", "ply`\nformat ascii 1.0\nelement vertex 0\nend_header\n");
  expectError([&] { loadMesh(magic); }, {magic, "first line is not 'ply'"});
  const auto no_end = writeFile("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
  expectError([&] { loadMesh(no_end); }, {no_end, "no end_header"});
  // The counts of a valid file pass (comments before them too).
  const auto ok =
      writeFile("ok.off", "OFF\n# a comment\n3 1 0\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n");
  EXPECT_EQ(loadMesh(ok).triangles.size(), 1u);
}

// Faces of more than three corners are split by the loader. The L-shaped top of a prism is
// concave: a fan from its first corner would leave the outline and double-count area.
TEST(MeshIo, ConcavePolygonFacesAreTriangulatedInsideTheirOutline) {
  const auto path = writeFile("l_panel.obj",
                              "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                              "f 1 2 3 4 5 6\n");
  MeshLoadReport report;
  const TriangleMesh mesh = loadMesh(path, {}, &report);
  EXPECT_EQ(mesh.triangleCount(), 4u);
  EXPECT_EQ(report.triangulated_polygons, 1u);
  EXPECT_NEAR(mesh.surfaceArea(), 3.0, 1e-6);
  for (const Triangle& t : mesh.triangles) {
    const auto& v = mesh.vertices;
    EXPECT_GT((v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).z(), 0.0f) << "a triangle is flipped";
  }
}

TEST(MeshValidation, UnitScale) {
  // A 180 mm part stored in millimetres is 180 m large: rejected with a hint, loads with scale.
  std::string obj = "v 0 0 0\nv 180 0 0\nv 0 87 0\nv 0 0 42\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const auto path = writeFile("mm.obj", obj);
  MeshLoadOptions opts;
  opts.max_extent_m = 5.0f;
  expectError([&] { loadMesh(path, opts); }, {path, "180", "0.001"});
  opts.scale = 0.001f;
  const TriangleMesh mesh = loadMesh(path, opts);
  EXPECT_NEAR(mesh.boundingBox().sizes().x(), 0.18f, 1e-6f);
  opts.scale = -1.0f;
  expectError([&] { loadMesh(path, opts); }, {"scale"});
}

TEST(MeshMeasures, SamplingIsUniformOverArea) {
  // Two triangles of area 1 and 3 in separate planes: samples split 1:3 and lie on them.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 1}, {0, 3, 1}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  const SurfaceSample s = sampleSurface(mesh, 40000, 3);
  ASSERT_EQ(s.points.size(), 40000u);
  int upper = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const auto& p = s.points[i];
    const bool top = p.z() > 0.5f;
    upper += top;
    EXPECT_NEAR(p.z(), top ? 1.0f : 0.0f, 1e-6f);
    EXPECT_NEAR(std::abs(s.normals[i].z()), 1.0f, 1e-6f);
    EXPECT_LE(p.x() / 2.0f + p.y() / (top ? 3.0f : 1.0f), 1.0f + 1e-5f);
  }
  EXPECT_NEAR(upper / 40000.0, 0.75, 0.01);
}

TEST(MeshIo, SaveStlRoundTrip) {
  TriangleMesh mesh = loadMesh(writeFile("rt.obj", kTetObj));
  const std::string path = test::tempDir() + "/rt.stl";
  saveStl(mesh, path);
  const TriangleMesh back = loadMesh(path);
  EXPECT_EQ(back.triangleCount(), 4u);
  EXPECT_NEAR(back.surfaceArea(), mesh.surfaceArea(), 1e-6);
}

TEST(MeshIo, ResolvesPackageUris) {
  EXPECT_EQ(resolveResourcePath("file:///a/b.stl"), "/a/b.stl");
  EXPECT_EQ(resolveResourcePath("b.stl", "/a"), "/a/b.stl");
  const std::string p = resolveResourcePath("package://scene_graph_tracker/package.xml");
  EXPECT_TRUE(std::filesystem::exists(p)) << p;
  EXPECT_THROW(resolveResourcePath("package://no_such_package_xyz/a.stl"), MeshError);
}

TEST(MeshPaperObjects, LoadWithTheirTriangleCounts) {
  SGT_REQUIRE_PBR_OBJECTS(dir);
  const std::vector<std::pair<std::string, std::size_t>> expected = {
      {"multimeter/multimeter.stl", 33446},
      {"screwdriver/screwdriver.stl", 8894},
      {"materialbox/materialbox.stl", 4539},
      {"klt/klt3147.stl", 4708},
      {"relay/relay.stl", 3104}};
  for (const auto& [file, count] : expected) {
    MeshLoadReport report;
    const TriangleMesh m = loadMesh(dir + "/meshes/" + file, {}, &report);
    EXPECT_NEAR(static_cast<double>(m.triangleCount() + report.dropped_degenerate), count, 0)
        << file;
    EXPECT_LT(m.boundingBox().sizes().maxCoeff(), 0.31f) << file;
  }
}

}  // namespace
}  // namespace sgt
