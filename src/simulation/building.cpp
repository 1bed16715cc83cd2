#include "scene_graph_tracker/simulation/building.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "scene_graph_tracker/geometry/primitives.hpp"

namespace sgt {
namespace {

using Eigen::AlignedBox2f;
using Eigen::AlignedBox3f;
using Eigen::Vector2f;
using Eigen::Vector3f;

// Everything in the building is a set of faces of an axis-aligned box.
struct Piece {
  AlignedBox3f box;
  std::uint8_t faces;
};

struct Layout {
  std::vector<Piece> pieces;
  std::vector<AlignedBox2f> keep_out;  // floor areas furniture must not use (doors, corridors)
};

AlignedBox3f box3(float x0, float y0, float z0, float x1, float y1, float z1) {
  return AlignedBox3f(Vector3f(x0, y0, z0), Vector3f(x1, y1, z1));
}

AlignedBox2f box2(float x0, float y0, float x1, float y1) {
  return AlignedBox2f(Vector2f(x0, y0), Vector2f(x1, y1));
}

// Uniform numbers from mt19937 without the implementation-defined std distributions, so the
// layout is the same with every standard library.
struct Rng {
  std::mt19937 engine;
  float uniform(float a, float b) {
    return a + (b - a) * static_cast<float>(engine() >> 8) / 16777216.0f;
  }
  int integer(int lo, int hi) {
    return lo + static_cast<int>(engine() % static_cast<unsigned>(hi - lo + 1));
  }
};

int segments(float len, float tile) {
  return std::max(1, static_cast<int>(std::lround(len / tile)));
}

// Triangles appendBox emits for `layout` at quad size `tile` (same rounding), without building.
std::size_t triangleCount(const Layout& layout, float tile) {
  struct FaceAxes {
    std::uint8_t bit;
    int u, v;
  };
  const FaceAxes kFaces[6] = {{kFaceNegX, 1, 2}, {kFacePosX, 1, 2}, {kFaceNegY, 0, 2},
                              {kFacePosY, 0, 2}, {kFaceNegZ, 0, 1}, {kFacePosZ, 0, 1}};
  std::size_t n = 0;
  for (const Piece& p : layout.pieces) {
    const Vector3f d = p.box.sizes();
    for (const FaceAxes& f : kFaces)
      if ((p.faces & f.bit) && d[f.u] > 0.0f && d[f.v] > 0.0f)
        n += 2 * static_cast<std::size_t>(segments(d[f.u], tile)) * segments(d[f.v], tile);
  }
  return n;
}

// A straight wall of thickness t along `axis` (0: x, 1: y) centred on coordinate c of the other
// axis, from s0 to s1, full height h, with door openings [d0, d1] up to door_h under a lintel.
// Ends abutting other walls get no face; door jambs do.
void addWall(Layout& L, int axis, float c, float s0, float s1, float t, float h, float door_h,
             const std::vector<Vector2f>& doors) {
  const std::uint8_t sides = axis == 0 ? (kFaceNegY | kFacePosY) : (kFaceNegX | kFacePosX);
  const std::uint8_t end_lo = axis == 0 ? kFaceNegX : kFaceNegY;
  const std::uint8_t end_hi = axis == 0 ? kFacePosX : kFacePosY;
  auto add = [&](float a, float b, float z0, float z1, std::uint8_t faces) {
    if (b - a <= 1e-4f || z1 - z0 <= 1e-4f) return;
    L.pieces.push_back({axis == 0 ? box3(a, c - 0.5f * t, z0, b, c + 0.5f * t, z1)
                                  : box3(c - 0.5f * t, a, z0, c + 0.5f * t, b, z1),
                        faces});
  };
  float start = s0;
  std::uint8_t start_face = 0;
  for (const Vector2f& d : doors) {
    add(start, d.x(), 0.0f, h, sides | start_face | end_hi);
    add(d.x(), d.y(), door_h, h, sides | kFaceNegZ);  // lintel
    start = d.y();
    start_face = end_lo;
    const float m = 1.2f;  // keep the approach on both sides free
    L.keep_out.push_back(axis == 0 ? box2(d.x() - 0.3f, c - m, d.y() + 0.3f, c + m)
                                   : box2(c - m, d.x() - 0.3f, c + m, d.y() + 0.3f));
  }
  add(start, s1, 0.0f, h, sides | start_face);
}

// One door per room side, at a seeded position along [lo, hi].
std::vector<Vector2f> doorIn(Rng& rng, float lo, float hi, float width) {
  const float margin = 0.3f + 0.5f * width;
  if (hi - lo < 2.0f * margin) return {};
  const float centre = rng.uniform(lo + margin, hi - margin);
  return {Vector2f(centre - 0.5f * width, centre + 0.5f * width)};
}

bool freeSpot(const Layout& L, const AlignedBox2f& fp) {
  const AlignedBox2f grown(fp.min() - Vector2f::Constant(0.3f),
                           fp.max() + Vector2f::Constant(0.3f));
  return std::none_of(L.keep_out.begin(), L.keep_out.end(),
                      [&](const AlignedBox2f& k) { return k.intersects(grown); });
}

void addTable(Layout& L, const AlignedBox2f& fp, float top) {
  const float slab = 0.04f, leg = 0.05f, inset = 0.03f;
  const Vector2f a = fp.min(), b = fp.max();
  L.pieces.push_back({box3(a.x(), a.y(), top - slab, b.x(), b.y(), top), kAllFaces});
  for (float x : {a.x() + inset, b.x() - inset - leg})
    for (float y : {a.y() + inset, b.y() - inset - leg})
      L.pieces.push_back({box3(x, y, 0, x + leg, y + leg, top - slab),
                          kFaceNegX | kFacePosX | kFaceNegY | kFacePosY});
}

// Open shelf unit: back panel on side `back` (0: -x, 1: +x, 2: -y, 3: +y), two side panels,
// evenly spaced boards.
void addShelf(Layout& L, const AlignedBox2f& fp, int back, float height, int boards) {
  const float p = 0.02f;
  const Vector2f a = fp.min(), b = fp.max();
  const bool along_y = back < 2;  // shelf runs along y when its back is against an x wall
  const float bx0 = back == 0 ? a.x() : back == 1 ? b.x() - p : a.x();
  const float by0 = back == 2 ? a.y() : back == 3 ? b.y() - p : a.y();
  L.pieces.push_back({along_y ? box3(bx0, a.y(), 0, bx0 + p, b.y(), height)
                              : box3(a.x(), by0, 0, b.x(), by0 + p, height),
                      kAllFaces & ~kFaceNegZ});
  for (int s = 0; s < 2; ++s) {
    const AlignedBox3f side =
        along_y ? box3(a.x(), s ? b.y() - p : a.y(), 0, b.x(), s ? b.y() : a.y() + p, height)
                : box3(s ? b.x() - p : a.x(), a.y(), 0, s ? b.x() : a.x() + p, b.y(), height);
    L.pieces.push_back({side, kAllFaces & ~kFaceNegZ});
  }
  for (int k = 0; k < boards; ++k) {
    const float z =
        0.1f + (height - 0.12f) * static_cast<float>(k) / static_cast<float>(boards - 1);
    L.pieces.push_back({box3(a.x(), a.y(), z, b.x(), b.y(), z + p), kAllFaces});
  }
}

// Up to `count` seeded pieces of furniture inside `room`, avoiding doors and each other.
void furnishRoom(Layout& L, Rng& rng, const AlignedBox3f& room, int count, float height) {
  const Vector2f lo = room.min().head<2>(), hi = room.max().head<2>();
  for (int item = 0; item < count; ++item) {
    const int kind = rng.integer(0, 3);
    for (int attempt = 0; attempt < 30; ++attempt) {
      AlignedBox2f fp;
      int back = 0;
      if (kind == 1) {  // shelf against a wall
        back = rng.integer(0, 3);
        const float len = rng.uniform(0.8f, 2.4f), depth = rng.uniform(0.35f, 0.5f);
        const bool along_y = back < 2;
        const float span = along_y ? hi.y() - lo.y() : hi.x() - lo.x();
        if (span < len + 0.2f) continue;
        const float s = (along_y ? lo.y() : lo.x()) + 0.1f + rng.uniform(0.0f, span - len - 0.2f);
        const float w0 =
            along_y ? (back == 0 ? lo.x() : hi.x() - depth) : (back == 2 ? lo.y() : hi.y() - depth);
        fp = along_y ? box2(w0, s, w0 + depth, s + len) : box2(s, w0, s + len, w0 + depth);
      } else {
        Vector2f size;
        if (kind == 0) size = Vector2f(rng.uniform(1.0f, 2.2f), rng.uniform(0.6f, 1.0f));
        if (kind == 2) size = Vector2f::Constant(rng.uniform(0.3f, 0.5f));
        if (kind == 3) size = Vector2f(rng.uniform(0.5f, 1.2f), rng.uniform(0.4f, 0.7f));
        if (rng.integer(0, 1)) std::swap(size.x(), size.y());
        const Vector2f room_lo = lo + Vector2f::Constant(0.5f),
                       room_hi = hi - size - Vector2f::Constant(0.5f);
        if ((room_hi.array() <= room_lo.array()).any()) continue;
        const Vector2f at(rng.uniform(room_lo.x(), room_hi.x()),
                          rng.uniform(room_lo.y(), room_hi.y()));
        fp = AlignedBox2f(at, at + size);
      }
      if (!freeSpot(L, fp)) continue;
      const Vector2f a = fp.min(), b = fp.max();
      if (kind == 0) addTable(L, fp, rng.uniform(0.72f, 0.8f));
      if (kind == 1) addShelf(L, fp, back, rng.uniform(1.6f, 2.2f), rng.integer(3, 6));
      if (kind == 2)  // pillar, floor to ceiling
        L.pieces.push_back({box3(a.x(), a.y(), 0, b.x(), b.y(), height),
                            kFaceNegX | kFacePosX | kFaceNegY | kFacePosY});
      if (kind == 3)  // cabinet
        L.pieces.push_back(
            {box3(a.x(), a.y(), 0, b.x(), b.y(), rng.uniform(0.8f, 1.3f)), kAllFaces & ~kFaceNegZ});
      L.keep_out.push_back(fp);
      break;
    }
  }
}

}  // namespace

Building makeBuilding(const BuildingOptions& o) {
  Building out;
  Layout L;
  Rng rng{std::mt19937(o.seed)};
  const float lx = o.length_x, ly = o.length_y, t = o.wall_thickness, h = o.wall_height;
  const int nx = std::max(o.rooms_x, 1), ny = std::max(o.rooms_y, 1);
  auto xAt = [&](int i) { return lx * static_cast<float>(i) / static_cast<float>(nx); };
  auto yAt = [&](int j) { return ly * static_cast<float>(j) / static_cast<float>(ny); };
  // Free interior of room column i / row j along its axis.
  auto xLo = [&](int i) { return i == 0 ? t : xAt(i) + 0.5f * t; };
  auto xHi = [&](int i) { return i == nx - 1 ? lx - t : xAt(i + 1) - 0.5f * t; };
  auto yLo = [&](int j) { return j == 0 ? t : yAt(j) + 0.5f * t; };
  auto yHi = [&](int j) { return j == ny - 1 ? ly - t : yAt(j + 1) - 0.5f * t; };

  // Outer walls: the two along x run the full length, the two along y fit between them.
  const std::uint8_t x_faces = kFaceNegY | kFacePosY | kFaceNegX | kFacePosX;
  L.pieces.push_back({box3(0, 0, 0, lx, t, h), x_faces});
  L.pieces.push_back({box3(0, ly - t, 0, lx, ly, h), x_faces});
  L.pieces.push_back({box3(0, t, 0, t, ly - t, h), kFaceNegX | kFacePosX});
  L.pieces.push_back({box3(lx - t, t, 0, lx, ly - t, h), kFaceNegX | kFacePosX});
  // Interior walls along y run through; those along x fit between them. One door per room side.
  for (int i = 1; i < nx; ++i) {
    std::vector<Vector2f> doors;
    for (int j = 0; j < ny; ++j)
      for (const Vector2f& d : doorIn(rng, yLo(j), yHi(j), o.door_width)) doors.push_back(d);
    addWall(L, 1, xAt(i), t, ly - t, t, h, o.door_height, doors);
  }
  for (int j = 1; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      addWall(L, 0, yAt(j), xLo(i), xHi(i), t, h, o.door_height,
              doorIn(rng, xLo(i), xHi(i), o.door_width));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) out.rooms.push_back(box3(xLo(i), yLo(j), 0, xHi(i), yHi(j), h));

  // Workbench in room 0, near (3.0, 2.0), with the robot start ~2 m in front of it (+y).
  const AlignedBox3f& r0 = out.rooms.front();
  out.workbench_size = Vector2f(1.6f, 0.8f);
  const float bench_top = 0.75f;
  const float wx = std::min(3.0f, r0.center().x());
  const float wy = std::min(2.0f, r0.center().y() - 0.8f);
  const float ry = std::min(wy + 2.0f, r0.max().y() - 0.4f);
  out.workbench_top_centre = Vector3f(wx, wy, bench_top);
  out.robot_start = Vector3f(wx, ry, 0.0f);
  const AlignedBox2f bench(Vector2f(wx, wy) - 0.5f * out.workbench_size,
                           Vector2f(wx, wy) + 0.5f * out.workbench_size);
  addTable(L, bench, bench_top);
  L.keep_out.push_back(box2(wx - 1.0f, wy - 0.7f, wx + 1.0f, ry + 0.8f));  // bench to robot
  if (o.furniture) {
    for (std::size_t r = 0; r < out.rooms.size(); ++r)
      furnishRoom(L, rng, out.rooms[r], r == 0 ? 4 : rng.integer(1, 7), h);
  }

  // Tessellation. Walls and furniture use the quad size whose count (with floor and ceiling at
  // the same size) is nearest the target; all pieces change their rounding at similar sizes, so
  // the count moves in steps. The floor and ceiling grids then take up the remainder exactly.
  float tile = o.tile_size > 0.0f ? o.tile_size : 0.25f;
  int grid_x = segments(lx, tile), grid_y = segments(ly, tile);
  if (o.target_triangles > 0) {
    const auto target = static_cast<double>(o.target_triangles);
    auto total = [&](double log_tile) {
      const auto q = static_cast<float>(std::exp(log_tile));
      return static_cast<double>(triangleCount(L, q)) + 4.0 * segments(lx, q) * segments(ly, q);
    };
    double lo = std::log(0.005), hi = std::log(static_cast<double>(std::max(lx, ly)));
    for (int it = 0; it < 40; ++it) (total(0.5 * (lo + hi)) > target ? lo : hi) = 0.5 * (lo + hi);
    tile = static_cast<float>(std::exp(hi));
    const double quads = std::max(1.0, (target - triangleCount(L, tile)) / 4.0);  // per surface
    // About square floor quads; among nearby row counts take the one whose product fits best.
    const double rows = std::sqrt(quads * ly / lx);
    double best_err = std::numeric_limits<double>::infinity();
    for (int gy = std::max(1, static_cast<int>(0.9 * rows)); gy <= 1.1 * rows + 1.0; ++gy) {
      const int gx = std::max(1, static_cast<int>(std::lround(quads / gy)));
      const double err = std::abs(static_cast<double>(gx) * gy - quads);
      if (err < best_err) best_err = err, grid_x = gx, grid_y = gy;
    }
  }
  out.tile_size = tile;
  out.mesh.triangles.reserve(triangleCount(L, tile) + 4 * grid_x * grid_y);
  // Floor at z = 0 facing up, ceiling at the wall height facing down.
  appendQuadGrid(out.mesh, Vector3f::Zero(), Vector3f(lx, 0, 0), Vector3f(0, ly, 0), grid_x,
                 grid_y);
  appendQuadGrid(out.mesh, Vector3f(0, 0, h), Vector3f(0, ly, 0), Vector3f(lx, 0, 0), grid_y,
                 grid_x);
  for (const Piece& p : L.pieces) appendBox(out.mesh, p.box, tile, p.faces);
  return out;
}

}  // namespace sgt
