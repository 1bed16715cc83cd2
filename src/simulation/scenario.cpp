#include "scene_graph_tracker/simulation/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"

namespace fs = std::filesystem;

namespace sgt::sim {

// ---------------------------------------------------------------------------- trajectories
PoseTrajectory::PoseTrajectory(std::vector<PoseKey> keys) : keys_(std::move(keys)) {
  if (keys_.empty()) throw std::invalid_argument("PoseTrajectory: no keys");
  for (std::size_t i = 1; i < keys_.size(); ++i)
    if (!(keys_[i].t > keys_[i - 1].t))
      throw std::invalid_argument("PoseTrajectory: key times must increase");
  for (auto& k : keys_) k.orientation.normalize();
}

Eigen::Isometry3d PoseTrajectory::at(double t) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (keys_.empty()) return T;
  const PoseKey* a = &keys_.front();
  const PoseKey* b = a;
  double s = 0.0;
  if (t >= keys_.back().t) {
    a = b = &keys_.back();
  } else if (t > keys_.front().t) {
    const auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
                                     [](double v, const PoseKey& k) { return v < k.t; });
    b = &*it;
    a = &*(it - 1);
    s = (t - a->t) / (b->t - a->t);
  }
  T.translation() = a->position + s * (b->position - a->position);
  T.linear() = a->orientation.slerp(s, b->orientation).normalized().toRotationMatrix();
  return T;
}

Eigen::Quaterniond fromRpy(const Eigen::Vector3d& rpy) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()));
}

const ObjectSpec* Scenario::findObject(const std::string& id) const {
  for (const auto& o : objects)
    if (o.id == id) return &o;
  return nullptr;
}

std::vector<std::int64_t> frameTimesNs(double rate, double duration) {
  std::vector<std::int64_t> out;
  if (!(rate > 0.0) || !(duration > 0.0)) return out;
  const auto n = static_cast<std::int64_t>(std::ceil(duration * rate - 1e-9));
  for (std::int64_t k = 0; k < n; ++k)
    out.push_back(std::llround(static_cast<double>(k) * 1e9 / rate));
  return out;
}

// ---------------------------------------------------------------------------- YAML reading
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kMaxBuildingSize = 1000.0;  // m, any side of a generated building
constexpr double kMaxFloorQuads = 2.5e7;     // floor and ceiling alone: target_triangles' limit

// A YAML node with the file it came from and its path in the document, for error messages
// "file:line: path: message".
class Field {
 public:
  Field(const std::string& file, YAML::Node node, std::string path, int fallback_line)
      : file_(&file),
        node_(std::move(node)),
        path_(std::move(path)),
        fallback_line_(fallback_line) {}

  const std::string& path() const { return path_; }
  int line() const { return node_.Mark().line >= 0 ? node_.Mark().line + 1 : fallback_line_; }
  [[noreturn]] void fail(const std::string& message) const {
    throw ScenarioError(*file_ + ":" + std::to_string(line()) + ": " +
                        (path_.empty() ? "" : path_ + ": ") + message);
  }

  bool isNull() const { return !node_ || node_.IsNull(); }
  bool isMap() const { return node_.IsMap(); }
  bool isSequence() const { return node_.IsSequence(); }

  void expectMap() const {
    if (!node_.IsMap()) fail("expected a map (key: value, ...)");
  }
  // Every key must be one of `allowed`; an unknown key is an error naming it (and the known ones).
  void allowKeys(std::initializer_list<const char*> allowed) const {
    expectMap();
    for (const auto& kv : node_) {
      const std::string key = kv.first.Scalar();
      if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }) !=
          allowed.end())
        continue;
      std::string known;
      for (const char* a : allowed) known += std::string(known.empty() ? "" : ", ") + a;
      Field(*file_, kv.first, child(key), line())
          .fail("unknown key (expected one of: " + known + ")");
    }
  }
  bool has(const char* key) const { return node_.IsMap() && node_[key]; }
  std::optional<Field> optional(const char* key) const {
    if (!has(key)) return std::nullopt;
    return Field(*file_, node_[key], child(key), line());
  }
  Field required(const char* key) const {
    expectMap();
    if (!has(key))
      Field(*file_, YAML::Node(), child(key), line()).fail("required field is missing");
    return Field(*file_, node_[key], child(key), line());
  }

  std::size_t size() const { return node_.size(); }
  Field operator[](std::size_t i) const {
    return Field(*file_, node_[i], path_ + "[" + std::to_string(i) + "]", line());
  }
  // A list (possibly empty; a missing or null value counts as empty).
  std::vector<Field> list() const {
    std::vector<Field> out;
    if (isNull()) return out;
    if (!node_.IsSequence()) fail("expected a list");
    for (std::size_t i = 0; i < node_.size(); ++i) out.push_back((*this)[i]);
    return out;
  }

  double number() const {
    double v = 0.0;
    if (!node_.IsScalar() || !YAML::convert<double>::decode(node_, v)) fail("expected a number");
    if (!std::isfinite(v)) fail("expected a finite number");
    return v;
  }
  double positive() const {
    const double v = number();
    if (!(v > 0.0)) fail("expected a number > 0");
    return v;
  }
  double nonNegative() const {
    const double v = number();
    if (v < 0.0) fail("expected a number >= 0");
    return v;
  }
  double probability() const {
    const double v = number();
    if (v < 0.0 || v > 1.0) fail("expected a number in 0..1");
    return v;
  }
  long long integer(long long lo, long long hi) const {
    long long v = 0;
    if (!node_.IsScalar() || !YAML::convert<long long>::decode(node_, v))
      fail("expected a whole number");
    if (v < lo || v > hi)
      fail("expected a whole number in " + std::to_string(lo) + ".." + std::to_string(hi) +
           ", got " + std::to_string(v));
    return v;
  }
  bool boolean() const {
    bool v = false;
    if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, v)) fail("expected true or false");
    return v;
  }
  std::string string() const {
    if (!node_.IsScalar() || node_.Scalar().empty()) fail("expected a non-empty string");
    return node_.Scalar();
  }
  std::vector<double> numbers(std::size_t n) const {
    if (!node_.IsSequence()) fail("expected a list of " + std::to_string(n) + " numbers");
    if (node_.size() != n)
      fail("expected a list of " + std::to_string(n) + " numbers, got " +
           std::to_string(node_.size()));
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back((*this)[i].number());
    return v;
  }
  Eigen::Vector3d vec3() const {
    const auto v = numbers(3);
    return Eigen::Vector3d(v[0], v[1], v[2]);
  }
  Eigen::Vector3f color() const {
    const Eigen::Vector3d c = vec3();
    if ((c.array() < 0.0).any() || (c.array() > 1.0).any())
      fail("expected three numbers in 0..1 (RGB)");
    return c.cast<float>();
  }

 private:
  std::string child(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  const std::string* file_;
  YAML::Node node_;
  std::string path_;
  int fallback_line_;
};

class Parser {
 public:
  Parser(const std::string& path, const ScenarioLoadOptions& options) : options_(options) {
    s_.file = path;
    dir_ = fs::path(path).parent_path().string();
  }

  Scenario parse() {
    YAML::Node root;
    try {
      root = YAML::LoadFile(s_.file);
    } catch (const YAML::BadFile&) {
      throw ScenarioError(s_.file + ": cannot read the file");
    } catch (const YAML::ParserException& e) {
      throw ScenarioError(s_.file + ":" + std::to_string(e.mark.line + 1) +
                          ": YAML syntax error: " + e.msg);
    }
    const Field r(s_.file, root, "", 1);
    if (!root.IsMap())
      r.fail("expected a map of scenario fields (duration, world, catalog, objects, ...)");
    r.allowKeys({"duration", "seed", "start_time", "world", "catalog", "mesh_dir", "objects",
                 "distractors", "robot", "camera", "lidar", "noise", "detections", "relations"});

    s_.duration = r.required("duration").positive();
    if (const auto f = r.optional("seed"))
      s_.seed = static_cast<std::uint32_t>(f->integer(0, 4294967295LL));
    if (const auto f = r.optional("start_time")) s_.start_time = f->positive();

    parseWorld(r.required("world"));
    parseCatalog(r);
    parseRobot(r.required("robot"));
    std::set<std::string> ids;
    if (const auto f = r.optional("objects"))
      for (const Field& o : f->list()) parseObject(o, ids);
    if (const auto f = r.optional("distractors"))
      for (const Field& d : f->list()) parseDistractor(d, ids);
    for (std::size_t i = 0; i < inside_fields_.size(); ++i) {
      const auto& [index, field] = inside_fields_[i];
      const ObjectSpec& o = s_.objects[index];
      const ObjectSpec* c = s_.findObject(o.inside->container);
      if (!c || c == &o)
        field.fail("'" + o.inside->container + "' is not the id of another object");
    }
    if (const auto f = r.optional("relations"))
      for (const Field& rel : f->list()) parseRelation(rel);
    for (const ObjectSpec& o : s_.objects)
      if (o.inside)
        s_.relations.push_back(
            {o.id, relations::Relation::In, o.inside->container, o.inside->from});
    if (const auto f = r.optional("camera"))
      parseCamera(*f);
    else
      s_.camera.T_base_camera = defaultCameraMount();
    if (const auto f = r.optional("lidar"))
      parseLidar(*f);
    else
      s_.lidar.T_base_lidar.translation() = Eigen::Vector3d(0, 0, 0.9);
    if (const auto f = r.optional("noise")) parseNoise(*f);
    if (const auto f = r.optional("detections")) parseDetections(*f);
    return std::move(s_);
  }

 private:
  // ----------------------------------------------------------------- world and catalog
  void parseWorld(const Field& w) {
    w.allowKeys({"building", "mesh", "urdf", "workbench"});
    const int kinds = w.has("building") + w.has("mesh") + w.has("urdf");
    if (kinds != 1) w.fail("give exactly one of building, mesh, urdf");
    if (const auto b = w.optional("building")) {
      s_.world.kind = WorldSpec::Kind::Building;
      if (!b->isNull()) parseBuilding(*b, s_.world.building);
      Building building = makeBuilding(s_.world.building);
      s_.workbench = building.workbench_top_centre.cast<double>();
      s_.static_map = std::make_shared<TriangleMesh>(std::move(building.mesh));
    } else {
      const bool urdf = w.has("urdf");
      const Field f = w.required(urdf ? "urdf" : "mesh");
      s_.world.kind = urdf ? WorldSpec::Kind::Urdf : WorldSpec::Kind::Mesh;
      try {
        s_.world.path = resolveResourcePath(f.string(), dir_);
        s_.static_map = std::make_shared<TriangleMesh>(urdf ? staticMapFromUrdf(s_.world.path)
                                                            : loadStaticMap(s_.world.path));
      } catch (const ScenarioError&) {
        throw;
      } catch (const std::exception& e) {
        f.fail(e.what());
      }
    }
    if (const auto f = w.optional("workbench")) s_.workbench = f->vec3();
  }

  void parseBuilding(const Field& b, BuildingOptions& o) {
    b.allowKeys({"length_x", "length_y", "wall_height", "wall_thickness", "rooms_x", "rooms_y",
                 "door_width", "door_height", "tile_size", "target_triangles", "seed",
                 "furniture"});
    // Sizes in metres: beyond a kilometre is a unit mistake (and beyond float range, no mesh).
    auto fl = [&](const char* key, float& v) {
      if (const auto f = b.optional(key)) {
        const double x = f->positive();
        if (x > kMaxBuildingSize) f->fail("expected at most " + fmt(kMaxBuildingSize) + " (m)");
        v = static_cast<float>(x);
      }
    };
    fl("length_x", o.length_x), fl("length_y", o.length_y), fl("wall_height", o.wall_height);
    fl("wall_thickness", o.wall_thickness), fl("door_width", o.door_width),
        fl("door_height", o.door_height);
    fl("tile_size", o.tile_size);
    if (const auto f = b.optional("rooms_x")) o.rooms_x = static_cast<int>(f->integer(1, 100));
    if (const auto f = b.optional("rooms_y")) o.rooms_y = static_cast<int>(f->integer(1, 100));
    if (const auto f = b.optional("target_triangles"))
      o.target_triangles = static_cast<std::size_t>(f->integer(0, 100000000));
    if (const auto f = b.optional("seed"))
      o.seed = static_cast<std::uint32_t>(f->integer(0, 4294967295LL));
    if (const auto f = b.optional("furniture")) o.furniture = f->boolean();
    // Without a triangle target, tile_size sets the tessellation: the floor and the ceiling have
    // (length_x / tile_size) x (length_y / tile_size) quads each (a tiny tile would not fit in
    // memory, nor its count in an int).
    if (o.target_triangles == 0) {
      const double tile = o.tile_size > 0.0f ? o.tile_size : 0.25;
      const double quads = std::ceil(o.length_x / tile) * std::ceil(o.length_y / tile);
      if (quads > kMaxFloorQuads)
        (b.has("tile_size") ? b.required("tile_size") : b)
            .fail("tile_size " + fmt(tile) + " m makes " + fmt(quads) + " floor quads (at most " +
                  fmt(kMaxFloorQuads) + "): a larger tile_size, or target_triangles");
    }
  }

  void parseCatalog(const Field& r) {
    const Field c = r.required("catalog");
    const auto md = r.optional("mesh_dir");
    try {
      s_.catalog_path = resolveResourcePath(c.string(), dir_);
    } catch (const std::exception& e) {
      c.fail(e.what());
    }
    if (!options_.mesh_dir_override.empty()) {
      s_.mesh_dir = options_.mesh_dir_override;
    } else if (md) {
      try {
        s_.mesh_dir = resolveResourcePath(md->string(), dir_);
      } catch (const std::exception& e) {
        md->fail(e.what());
      }
      if (!fs::is_directory(s_.mesh_dir)) md->fail("'" + s_.mesh_dir + "' is not a directory");
    }
    try {
      s_.catalog = std::make_shared<ObjectCatalog>(loadObjectCatalog(s_.catalog_path, s_.mesh_dir));
    } catch (const std::exception& e) {
      if (!options_.mesh_dir_override.empty())
        throw ScenarioError(s_.file + ": catalog with the mesh directory override '" + s_.mesh_dir +
                            "': " + e.what());
      if (md && std::string(e.what()).find(s_.mesh_dir) != std::string::npos) md->fail(e.what());
      c.fail(e.what());
    }
  }

  // ----------------------------------------------------------------- frames and trajectories
  // Offset of `frame:` (map or workbench) in the map frame.
  Eigen::Vector3d frameOrigin(const Field& owner) const {
    const auto f = owner.optional("frame");
    if (!f) return Eigen::Vector3d::Zero();
    const std::string name = f->string();
    if (name == "map") return Eigen::Vector3d::Zero();
    if (name != "workbench") f->fail("unknown frame '" + name + "' (expected map or workbench)");
    if (!s_.workbench) f->fail("frame 'workbench' needs world.building or world.workbench");
    return *s_.workbench;
  }

  static double angle(const Field& k, const char* rad_key, const char* deg_key, double fallback) {
    if (k.has(rad_key) && k.has(deg_key))
      k.fail(std::string("give ") + rad_key + " or " + deg_key + ", not both");
    if (const auto f = k.optional(rad_key)) return f->number();
    if (const auto f = k.optional(deg_key)) return f->number() * kDeg;
    return fallback;
  }

  // keyframes: [{t, xyz, rpy | rpy_deg}] in the frame whose origin is `origin`.
  PoseTrajectory parsePoseKeys(const Field& owner, const Eigen::Vector3d& origin) const {
    const Field list = owner.required("keyframes");
    if (!list.isSequence() || list.size() == 0)
      list.fail("expected a list of at least one keyframe {t, xyz, rpy}");
    std::vector<PoseKey> keys;
    for (const Field& k : list.list()) {
      k.allowKeys({"t", "xyz", "rpy", "rpy_deg"});
      PoseKey key;
      key.t = timeOf(k, keys);
      key.position = origin + k.required("xyz").vec3();
      if (k.has("rpy") && k.has("rpy_deg")) k.fail("give rpy or rpy_deg, not both");
      Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
      if (const auto f = k.optional("rpy")) rpy = f->vec3();
      if (const auto f = k.optional("rpy_deg")) rpy = f->vec3() * kDeg;
      key.orientation = fromRpy(rpy);
      keys.push_back(key);
    }
    return PoseTrajectory(std::move(keys));
  }

  static double timeOf(const Field& k, const std::vector<PoseKey>& previous) {
    const Field tf = k.required("t");
    const double t = tf.nonNegative();
    if (!previous.empty() && !(t > previous.back().t))
      tf.fail("keyframe times must increase (previous keyframe has t = " + fmt(previous.back().t) +
              ")");
    return t;
  }

  static std::string fmt(double v) {
    std::ostringstream ss;
    ss << v;
    return ss.str();
  }

  void parseRobot(const Field& r) {
    r.allowKeys({"frame", "keyframes"});
    const Eigen::Vector3d origin = frameOrigin(r);
    const Field list = r.required("keyframes");
    if (!list.isSequence() || list.size() == 0)
      list.fail("expected a list of at least one keyframe {t, xy, yaw}");
    std::vector<PoseKey> keys;
    for (const Field& k : list.list()) {
      k.allowKeys({"t", "xy", "yaw", "yaw_deg"});
      PoseKey key;
      key.t = timeOf(k, keys);
      const auto xy = k.required("xy").numbers(2);
      key.position = Eigen::Vector3d(origin.x() + xy[0], origin.y() + xy[1], 0.0);
      key.orientation = Eigen::Quaterniond(
          Eigen::AngleAxisd(angle(k, "yaw", "yaw_deg", 0.0), Eigen::Vector3d::UnitZ()));
      keys.push_back(key);
    }
    s_.robot = PoseTrajectory(std::move(keys));
  }

  void checkId(const Field& f, const std::string& id, std::set<std::string>& ids) const {
    if (!ids.insert(id).second) f.fail("duplicate id '" + id + "'");
  }

  void parseObject(const Field& o, std::set<std::string>& ids) {
    o.allowKeys({"id", "class", "frame", "keyframes", "inside", "color"});
    ObjectSpec spec;
    const Field idf = o.required("id");
    spec.id = idf.string();
    checkId(idf, spec.id, ids);
    const Field cls = o.required("class");
    spec.class_name = cls.string();
    if (!s_.catalog->contains(spec.class_name)) {
      std::string known;
      for (const auto& n : s_.catalog->names()) known += (known.empty() ? "" : ", ") + n;
      cls.fail("unknown class '" + spec.class_name + "' (catalog " + s_.catalog_path +
               " has: " + known + ")");
    }
    spec.trajectory = parsePoseKeys(o, frameOrigin(o));
    if (const auto f = o.optional("color")) spec.color = f->color();
    if (const auto f = o.optional("inside")) {
      f->allowKeys({"container", "from"});
      InsideAnnotation a;
      a.container = f->required("container").string();
      if (const auto from = f->optional("from")) a.from = from->nonNegative();
      spec.inside = a;
      inside_fields_.emplace_back(s_.objects.size(), f->required("container"));
    }
    s_.objects.push_back(std::move(spec));
  }

  // {subject: ID, relation: NAME, object: ID | workbench, from: t, to: t}
  void parseRelation(const Field& f) {
    f.allowKeys({"subject", "relation", "object", "from", "to"});
    RelationSpec spec;
    const Field subject = f.required("subject"), object = f.required("object"),
                relation = f.required("relation");
    spec.subject = subject.string();
    if (!s_.findObject(spec.subject))
      subject.fail("'" + spec.subject + "' is not the id of an object");
    spec.object = object.string();
    const bool furniture = spec.object == kWorkbenchName && s_.workbench.has_value();
    if (!furniture && !s_.findObject(spec.object))
      object.fail("'" + spec.object + "' is not the id of an object" +
                  (s_.workbench ? " or workbench" : ""));
    if (spec.object == spec.subject) object.fail("an object stands in no relation to itself");
    const auto r = relations::parseRelation(relation.string());
    if (!r)
      relation.fail("unknown relation '" + relation.string() +
                    "' (expected on, in, left_of, right_of, in_front_of, behind, above or below)");
    spec.relation = *r;
    if (const auto from = f.optional("from")) spec.from = from->nonNegative();
    if (const auto to = f.optional("to")) {
      spec.to = to->number();
      std::ostringstream from;
      from << spec.from;
      if (!(spec.to > spec.from)) to->fail("expected a time after from (" + from.str() + ")");
    }
    s_.relations.push_back(spec);
  }

  void parseDistractor(const Field& d, std::set<std::string>& ids) {
    d.allowKeys({"id", "shape", "size", "radius", "height", "frame", "keyframes", "color"});
    DistractorSpec spec;
    const Field idf = d.required("id");
    spec.id = idf.string();
    checkId(idf, spec.id, ids);
    const Field shape = d.required("shape");
    const std::string name = shape.string();
    auto forbid = [&](std::initializer_list<const char*> keys) {
      for (const char* k : keys)
        if (const auto f = d.optional(k)) f->fail("not used by shape '" + name + "'");
    };
    if (name == "box") {
      spec.shape = Shape::Box;
      const Field size = d.required("size");
      spec.size = size.vec3().cast<float>();
      if ((spec.size.array() <= 0.0f).any()) size.fail("expected three numbers > 0");
      forbid({"radius", "height"});
    } else if (name == "cylinder") {
      spec.shape = Shape::Cylinder;
      spec.radius = static_cast<float>(d.required("radius").positive());
      spec.height = static_cast<float>(d.required("height").positive());
      forbid({"size"});
    } else if (name == "sphere") {
      spec.shape = Shape::Sphere;
      spec.radius = static_cast<float>(d.required("radius").positive());
      forbid({"size", "height"});
    } else {
      shape.fail("unknown shape '" + name + "' (expected box, cylinder or sphere)");
    }
    spec.trajectory = parsePoseKeys(d, frameOrigin(d));
    if (const auto f = d.optional("color")) spec.color = f->color();
    s_.distractors.push_back(std::move(spec));
  }

  // ----------------------------------------------------------------- sensors
  // Optical frame in base_link for the default mount: 0.1 m ahead, 1.25 m up, looking ahead.
  static Eigen::Isometry3d defaultCameraMount() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.1, 0.0, 1.25);
    T.linear() = bodyToOptical();
    return T;
  }

  // Rotation from a camera body frame (x forward, y left, z up) to its optical frame.
  static Eigen::Matrix3d bodyToOptical() {
    Eigen::Matrix3d R;
    R.col(0) = Eigen::Vector3d(0, -1, 0);  // optical x = body -y
    R.col(1) = Eigen::Vector3d(0, 0, -1);  // optical y = body -z
    R.col(2) = Eigen::Vector3d(1, 0, 0);   // optical z = body x
    return R;
  }

  // mount: {xyz, rpy | rpy_deg | look_at (+ look_at_frame)}; returns the mounted body frame
  // (or the optical frame for look_at) in base_link.
  Eigen::Isometry3d parseMount(const Field& m, bool camera) const {
    if (camera)
      m.allowKeys({"xyz", "rpy", "rpy_deg", "look_at", "look_at_frame"});
    else
      m.allowKeys({"xyz", "rpy", "rpy_deg"});
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = m.required("xyz").vec3();
    const int given = m.has("rpy") + m.has("rpy_deg") + m.has("look_at");
    if (given > 1)
      m.fail(camera ? "give one of rpy, rpy_deg, look_at" : "give rpy or rpy_deg, not both");
    if (const auto f = m.optional("rpy")) T.linear() = fromRpy(f->vec3()).toRotationMatrix();
    if (const auto f = m.optional("rpy_deg"))
      T.linear() = fromRpy(f->vec3() * kDeg).toRotationMatrix();
    if (camera) {
      if (const auto la = m.optional("look_at")) {
        Eigen::Vector3d origin = Eigen::Vector3d::Zero();
        if (const auto lf = m.optional("look_at_frame")) {
          const std::string name = lf->string();
          if (name == "workbench") {
            if (!s_.workbench)
              lf->fail("frame 'workbench' needs world.building or world.workbench");
            origin = *s_.workbench;
          } else if (name != "map") {
            lf->fail("unknown frame '" + name + "' (expected map or workbench)");
          }
        }
        // Looks at the target from the robot's pose at its last keyframe; the mount is fixed.
        const Eigen::Isometry3d T_map_base = s_.robot.at(s_.robot.keys().back().t);
        const Eigen::Vector3d eye = T_map_base * T.translation(), target = origin + la->vec3();
        if ((target - eye).norm() < 1e-6) la->fail("the target is at the camera");
        if ((target - eye).normalized().cross(Eigen::Vector3d::UnitZ()).norm() < 1e-6)
          la->fail("the camera would look straight up or down: pick another target");
        const Eigen::Isometry3d T_base_opt = T_map_base.inverse() * opticalLookAt(eye, target);
        T.linear() = T_base_opt.linear();
        return T;
      }
      if (m.has("look_at_frame")) m.required("look_at_frame").fail("only used with look_at");
      T.linear() = T.linear() * bodyToOptical();
    }
    return T;
  }

  void parseCamera(const Field& c) {
    c.allowKeys(
        {"width", "height", "fx", "fy", "cx", "cy", "range_min", "range_max", "rate", "mount"});
    PinholeModel& m = s_.camera.model;
    if (const auto f = c.optional("width")) m.width = static_cast<int>(f->integer(1, 10000));
    if (const auto f = c.optional("height")) m.height = static_cast<int>(f->integer(1, 10000));
    if (const auto f = c.optional("fx")) m.fx = f->positive();
    if (const auto f = c.optional("fy")) m.fy = f->positive();
    m.cx = c.has("cx") ? c.required("cx").number() : 0.5 * (m.width - 1);
    m.cy = c.has("cy") ? c.required("cy").number() : 0.5 * (m.height - 1);
    if (const auto f = c.optional("range_min")) m.range_min = static_cast<float>(f->nonNegative());
    if (const auto f = c.optional("range_max")) m.range_max = static_cast<float>(f->positive());
    if (!(m.range_max > m.range_min)) c.required("range_max").fail("must be larger than range_min");
    if (const auto f = c.optional("rate")) s_.camera.rate = f->positive();
    s_.camera.T_base_camera =
        c.has("mount") ? parseMount(c.required("mount"), true) : defaultCameraMount();
  }

  void parseLidar(const Field& l) {
    l.allowKeys({"range_min", "range_max", "rate", "mount"});
    SpinningLidarModel& m = s_.lidar.model;
    if (const auto f = l.optional("range_min")) m.range_min = static_cast<float>(f->nonNegative());
    if (const auto f = l.optional("range_max")) m.range_max = static_cast<float>(f->positive());
    if (!(m.range_max > m.range_min)) l.required("range_max").fail("must be larger than range_min");
    if (const auto f = l.optional("rate")) s_.lidar.rate = f->positive();
    if (const auto f = l.optional("mount"))
      s_.lidar.T_base_lidar = parseMount(*f, false);
    else
      s_.lidar.T_base_lidar.translation() = Eigen::Vector3d(0, 0, 0.9);
  }

  // ----------------------------------------------------------------- noise and detections
  void parseNoise(const Field& n) {
    n.allowKeys({"depth_sigma_at_1m", "depth_edge_jump", "depth_max_incidence_deg",
                 "lidar_range_sigma", "odometry"});
    NoiseSpec& o = s_.noise;
    if (const auto f = n.optional("depth_sigma_at_1m")) o.depth_sigma_at_1m = f->nonNegative();
    if (const auto f = n.optional("depth_edge_jump")) o.depth_edge_jump = f->nonNegative();
    if (const auto f = n.optional("depth_max_incidence_deg")) {
      o.depth_max_incidence_deg = f->positive();
      if (o.depth_max_incidence_deg > 90.0) f->fail("expected an angle in 0..90 degrees");
    }
    if (const auto f = n.optional("lidar_range_sigma")) o.lidar_range_sigma = f->nonNegative();
    if (const auto od = n.optional("odometry")) {
      od->allowKeys({"translation_sigma", "rotation_sigma", "initial_error"});
      if (const auto f = od->optional("translation_sigma"))
        o.odom_translation_sigma = f->nonNegative();
      if (const auto f = od->optional("rotation_sigma")) o.odom_rotation_sigma = f->nonNegative();
      if (const auto f = od->optional("initial_error")) o.odom_initial_error = f->vec3();
    }
  }

  void parseDetections(const Field& d) {
    d.allowKeys({"enabled", "min_visible_pixels", "sigma_t", "sigma_r_deg", "miss_probability",
                 "false_positives_per_frame"});
    DetectionSpec& o = s_.detections;
    if (const auto f = d.optional("enabled")) o.enabled = f->boolean();
    if (const auto f = d.optional("min_visible_pixels"))
      o.min_visible_pixels = static_cast<int>(f->integer(1, 100000000));
    if (const auto f = d.optional("sigma_t")) o.sigma_t = f->nonNegative();
    if (const auto f = d.optional("sigma_r_deg")) o.sigma_r_deg = f->nonNegative();
    if (const auto f = d.optional("miss_probability")) o.miss_probability = f->probability();
    if (const auto f = d.optional("false_positives_per_frame"))
      o.false_positives_per_frame = f->nonNegative();
  }

  ScenarioLoadOptions options_;
  Scenario s_;
  std::string dir_;
  std::vector<std::pair<std::size_t, Field>> inside_fields_;
};

}  // namespace

Scenario loadScenario(const std::string& path, const ScenarioLoadOptions& options) {
  return Parser(path, options).parse();
}

}  // namespace sgt::sim
