#include "scene_graph_tracker/simulation/procedural_objects.hpp"

#include <cmath>
#include <stdexcept>

#include "scene_graph_tracker/geometry/primitives.hpp"

namespace sgt {
namespace {

using Eigen::Vector3f;

Eigen::Isometry3f at(const Vector3f& centre,
                     const Eigen::Matrix3f& R = Eigen::Matrix3f::Identity()) {
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  T.linear() = R;
  T.translation() = centre;
  return T;
}

Eigen::Matrix3f rotZ(float deg) {
  return Eigen::AngleAxisf(deg * static_cast<float>(M_PI) / 180.0f, Vector3f::UnitZ()).matrix();
}

// Cylinder axis z -> x.
const Eigen::Matrix3f kAlongX = Eigen::AngleAxisf(0.5f * M_PI, Vector3f::UnitY()).matrix();

void box(TriangleMesh& m, const Vector3f& size, const Vector3f& centre, int subdiv = 1,
         const Eigen::Matrix3f& R = Eigen::Matrix3f::Identity()) {
  m.append(makeBox(size, subdiv), at(centre, R));
}

// Handheld multimeter lying on its back: body, raised display window, rotary selector knob with a
// pointer ridge (breaks the knob's symmetry), two test-lead jacks and a row of buttons.
TriangleMesh multimeter() {
  TriangleMesh m;
  box(m, {0.180f, 0.087f, 0.030f}, {0, 0, 0.015f}, 4);
  box(m, {0.060f, 0.065f, 0.003f}, {0.050f, 0, 0.0315f}, 2);
  m.append(makeCylinder(0.022f, 0.008f, 48), at({-0.015f, 0, 0.034f}));
  box(m, {0.036f, 0.005f, 0.004f}, {-0.015f, 0, 0.040f}, 1, rotZ(30.0f));
  for (float y : {-0.022f, 0.022f})
    m.append(makeCylinder(0.0045f, 0.005f, 24), at({-0.067f, y, 0.0325f}));
  for (float y : {-0.027f, -0.009f, 0.009f, 0.027f})
    box(m, {0.008f, 0.012f, 0.002f}, {0.012f, y, 0.031f});
  return m;
}

// Screwdriver along x: handle with a ferrule, thin round shaft and a flat blade tip.
TriangleMesh screwdriver() {
  TriangleMesh m;
  m.append(makeCylinder(0.017f, 0.100f, 40), at({0.050f, 0, 0}, kAlongX));
  m.append(makeCylinder(0.006f, 0.010f, 24), at({0.105f, 0, 0}, kAlongX));
  m.append(makeCylinder(0.003f, 0.115f, 16), at({0.1675f, 0, 0}, kAlongX));
  box(m, {0.020f, 0.0055f, 0.0012f}, {0.235f, 0, 0});
  return m;
}

// Plastic storage box: body, slightly larger lid slab, lid grip and a front latch.
TriangleMesh materialbox() {
  TriangleMesh m;
  box(m, {0.169f, 0.120f, 0.078f}, {0, 0, 0.039f}, 3);
  box(m, {0.175f, 0.126f, 0.008f}, {0, 0, 0.082f}, 3);
  box(m, {0.070f, 0.016f, 0.002f}, {0, 0.020f, 0.087f});
  box(m, {0.030f, 0.003f, 0.012f}, {0, -0.0615f, 0.070f});
  return m;
}

// VDA KLT small load carrier: open crate with 6 mm walls and the 4 mm outward lip that runs
// around its top edge.
TriangleMesh klt() {
  TriangleMesh m = makeOpenBox({0.289f, 0.189f, 0.147f}, 0.006f, 4);
  const float z = 0.0635f;  // lip: the top 20 mm
  for (float y : {-0.0965f, 0.0965f}) box(m, {0.297f, 0.004f, 0.020f}, {0, y, z}, 2);
  for (float x : {-0.1465f, 0.1465f}) box(m, {0.004f, 0.189f, 0.020f}, {x, 0, z}, 2);
  return m;
}

// Plug-in relay: pins below, body, and an off-centre cap on top.
TriangleMesh relay() {
  TriangleMesh m;
  const float pins[5][2] = {
      {-0.017f, -0.013f}, {-0.017f, 0.013f}, {0.017f, -0.013f}, {0.017f, 0.013f}, {0.004f, 0.0f}};
  for (const auto& p : pins) box(m, {0.0015f, 0.006f, 0.008f}, {p[0], p[1], 0.004f});
  box(m, {0.058f, 0.045f, 0.082f}, {0, 0, 0.049f}, 3);
  box(m, {0.034f, 0.030f, 0.014f}, {0.008f, 0, 0.097f}, 2);
  return m;
}

struct ClassInfo {
  const char* name;
  Vector3f extents;
  std::size_t paper_triangles;
  TriangleMesh (*build)();
};

const ClassInfo& lookup(const std::string& name) {
  static const ClassInfo kClasses[] = {
      {"multimeter", {0.180f, 0.087f, 0.042f}, 33446, multimeter},
      {"screwdriver", {0.245f, 0.034f, 0.034f}, 8894, screwdriver},
      {"materialbox", {0.175f, 0.126f, 0.088f}, 4539, materialbox},
      {"klt", {0.297f, 0.197f, 0.147f}, 4708, klt},
      {"relay", {0.058f, 0.045f, 0.104f}, 3104, relay},
  };
  for (const auto& c : kClasses)
    if (name == c.name) return c;
  throw std::invalid_argument("unknown object class '" + name +
                              "' (known: multimeter, screwdriver, materialbox, klt, relay)");
}

}  // namespace

const std::vector<std::string>& paperObjectClasses() {
  static const std::vector<std::string> kNames = {"multimeter", "screwdriver", "materialbox", "klt",
                                                  "relay"};
  return kNames;
}

std::size_t paperTriangleCount(const std::string& class_name) {
  return lookup(class_name).paper_triangles;
}

Eigen::Vector3f paperObjectExtents(const std::string& class_name) {
  return lookup(class_name).extents;
}

TriangleMesh makeObjectModel(const std::string& class_name, std::size_t min_triangles) {
  const ClassInfo& info = lookup(class_name);
  TriangleMesh mesh = info.build();
  // Origin at the bounding-box centre, extents exactly those of the real object.
  const Eigen::AlignedBox3f box = mesh.boundingBox();
  const Vector3f centre = box.center();
  const Vector3f s = info.extents.cwiseQuotient(box.sizes());
  for (auto& v : mesh.vertices) v = (v - centre).cwiseProduct(s);
  if (min_triangles > 0) subdivideToAtLeast(mesh, min_triangles);
  return mesh;
}

}  // namespace sgt
