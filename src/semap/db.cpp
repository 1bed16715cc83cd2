#include "scene_graph_tracker/semap/db.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <pqxx/pqxx>
#include <sstream>
#include <stdexcept>

#include "scene_graph_tracker/util/package_files.hpp"

namespace sgt::semap {
namespace {

// Connections are opened one at a time in a process. libpqxx 6.4 (not built with ThreadSanitizer)
// shares state between connection set-ups: make test-tsan reported the bridge's writer thread and
// a service call opening theirs at once. Opening is rare (start-up, reconnects), so this costs
// nothing that matters.
std::mutex& connectMutex() {
  static std::mutex m;
  return m;
}

std::string quoted(const std::string& v) {
  std::string out = "'";
  for (char c : v) {
    if (c == '\'' || c == '\\') out += '\\';
    out += c;
  }
  return out + "'";
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("semap: cannot read " + path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string multipointWkt(const std::vector<Eigen::Vector3d>& points) {
  std::ostringstream s;
  s << std::setprecision(9) << "MULTIPOINT Z (";
  for (std::size_t i = 0; i < points.size(); ++i)
    s << (i ? ", " : "") << "(" << points[i].x() << " " << points[i].y() << " " << points[i].z()
      << ")";
  s << ")";
  return s.str();
}

std::optional<double> optionalDouble(const pqxx::field& f) {
  if (f.is_null()) return std::nullopt;
  return f.as<double>();
}

// Pose columns x y z qw qx qy qz starting at `first`.
Eigen::Isometry3d poseFrom(const pqxx::row& r, int first) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() =
      Eigen::Vector3d(r[first].as<double>(), r[first + 1].as<double>(), r[first + 2].as<double>());
  T.linear() = Eigen::Quaterniond(r[first + 3].as<double>(), r[first + 4].as<double>(),
                                  r[first + 5].as<double>(), r[first + 6].as<double>())
                   .normalized()
                   .toRotationMatrix();
  return T;
}

const char* kUpsertClass = R"SQL(
INSERT INTO object_class AS c (name, min_x, min_y, min_z, max_x, max_y, max_z, box, hull)
VALUES ($1, $2, $3, $4, $5, $6, $7, semap_aabb($2, $3, $4, $5, $6, $7),
        semap_hull(NULLIF($8, '')::geometry))
ON CONFLICT (name) DO UPDATE SET min_x = EXCLUDED.min_x, min_y = EXCLUDED.min_y, min_z = EXCLUDED.min_z,
  max_x = EXCLUDED.max_x, max_y = EXCLUDED.max_y, max_z = EXCLUDED.max_z, box = EXCLUDED.box,
  hull = COALESCE(EXCLUDED.hull, c.hull))SQL";

// $1 id, $2 class, $3 parent, $4 stamp (s), $5..$11 x y z qw qx qy qz, $12 robot
const char* kUpsertInstance = R"SQL(
INSERT INTO instance AS i (id, class_name, parent, first_seen, last_seen, present, x, y, z, qw, qx, qy, qz, box, robot)
SELECT $1, c.name, $3, to_timestamp($4), to_timestamp($4), true, $5, $6, $7, $8, $9, $10, $11,
       semap_place(c.box, $5, $6, $7, $8, $9, $10, $11), $12
FROM object_class c WHERE c.name = $2
ON CONFLICT (id) DO UPDATE SET class_name = EXCLUDED.class_name, parent = EXCLUDED.parent, robot = EXCLUDED.robot,
  last_seen = EXCLUDED.last_seen, present = true, x = EXCLUDED.x, y = EXCLUDED.y, z = EXCLUDED.z,
  qw = EXCLUDED.qw, qx = EXCLUDED.qx, qy = EXCLUDED.qy, qz = EXCLUDED.qz, box = EXCLUDED.box
WHERE i.last_seen <= EXCLUDED.last_seen)SQL";

// $1 id, $2 class, $3..$9 x y z qw qx qy qz: present and fixed from now on.
const char* kUpsertFixed = R"SQL(
INSERT INTO instance AS i (id, class_name, parent, first_seen, last_seen, present, fixed, x, y, z, qw, qx, qy, qz, box)
SELECT $1, c.name, 'map', now(), now(), true, true, $3, $4, $5, $6, $7, $8, $9,
       semap_place(c.box, $3, $4, $5, $6, $7, $8, $9)
FROM object_class c WHERE c.name = $2
ON CONFLICT (id) DO UPDATE SET class_name = EXCLUDED.class_name, parent = EXCLUDED.parent,
  last_seen = EXCLUDED.last_seen, present = true, fixed = true, x = EXCLUDED.x, y = EXCLUDED.y,
  z = EXCLUDED.z, qw = EXCLUDED.qw, qx = EXCLUDED.qx, qy = EXCLUDED.qy, qz = EXCLUDED.qz,
  box = EXCLUDED.box)SQL";

const char* kInsertPose = R"SQL(
INSERT INTO pose_history (instance_id, stamp, parent, x, y, z, qw, qx, qy, qz, position, box)
SELECT $1, to_timestamp($4), $3, $5, $6, $7, $8, $9, $10, $11, ST_MakePoint($5, $6, $7),
       semap_place(c.box, $5, $6, $7, $8, $9, $10, $11)
FROM object_class c WHERE c.name = $2
ON CONFLICT DO NOTHING)SQL";

}  // namespace

std::string DbSettings::connectionString() const {
  std::string s = "host=" + quoted(host) + " port=" + std::to_string(port) +
                  " user=" + quoted(user) + " dbname=" + quoted(dbname) +
                  " connect_timeout=" + std::to_string(connect_timeout_s) +
                  " application_name='scene_graph_tracker semap'";
  if (!password.empty()) s += " password=" + quoted(password);
  if (!passfile.empty()) s += " passfile=" + quoted(passfile);
  s += " keepalives=1 keepalives_idle=" + std::to_string(std::max(1, keepalive_idle_s)) +
       " keepalives_interval=2 keepalives_count=3 tcp_user_timeout=" +
       std::to_string(static_cast<long>(std::max(0.0, tcp_timeout_s) * 1000));
  return s;
}

std::string checkedMode(const std::string& mode) {
  if (mode.empty()) return "strict";
  if (mode != "strict" && mode != "relaxed")
    throw std::invalid_argument("mode must be 'strict' or 'relaxed', not '" + mode + "'");
  return mode;
}

void checkRelationName(const std::string& relation) {
  static const std::set<std::string> names = {"on",          "in",     "left_of", "right_of",
                                              "in_front_of", "behind", "above",   "below"};
  if (!relation.empty() && !names.count(relation))
    throw std::invalid_argument("unknown relation '" + relation +
                                "' (on, in, left_of, right_of, in_front_of, behind, above, below)");
}

struct SemapDb::Impl {
  explicit Impl(const std::string& conninfo) : conn(conninfo) {}
  pqxx::connection conn;
};

SemapDb::SemapDb(DbSettings settings) : settings_(std::move(settings)) {
  if (settings_.sql_dir.empty()) settings_.sql_dir = packageFile("sql");
  const std::lock_guard<std::mutex> lock(connectMutex());
  impl_ = std::make_unique<Impl>(settings_.connectionString());
  if (settings_.statement_timeout_s > 0)
    impl_->conn.set_variable(
        "statement_timeout",
        std::to_string(static_cast<int>(settings_.statement_timeout_s * 1000)));
}

SemapDb::~SemapDb() = default;

bool SemapDb::isOpen() const { return impl_ && impl_->conn.is_open(); }

void SemapDb::installSchema() {
  const std::string schema = readFile(settings_.sql_dir + "/semap_schema.sql");
  const std::string relations = readFile(settings_.sql_dir + "/semap_relations.sql");
  pqxx::work w(impl_->conn);
  w.exec("SELECT pg_advisory_xact_lock(7362770)");    // one installer at a time
  w.exec("SET LOCAL client_min_messages = warning");  // no "already exists, skipping" notices
  w.exec(schema);
  w.exec(relations);
  w.commit();
}

SemapDb::WriteResult SemapDb::writeFrame(const Frame& frame) {
  relation_error_.clear();
  WriteResult result;
  pqxx::work w(impl_->conn);
  std::set<std::string> new_classes;
  for (const InstancePose& o : frame.objects) {
    if (!o.shape || classes_written_.count(o.shape->name) || new_classes.count(o.shape->name))
      continue;
    const Eigen::AlignedBox3d& b = o.shape->box;
    w.exec_params(kUpsertClass, o.shape->name, b.min().x(), b.min().y(), b.min().z(), b.max().x(),
                  b.max().y(), b.max().z(),
                  o.shape->hull_points.size() >= 4 ? multipointWkt(o.shape->hull_points) : "");
    new_classes.insert(o.shape->name);
  }
  for (const InstancePose& o : frame.objects) {
    if (!o.shape) continue;
    const Eigen::Vector3d t = o.T_world_object.translation();
    const Eigen::Quaterniond q(o.T_world_object.rotation());
    w.exec_params(kUpsertInstance, o.id, o.shape->name, o.parent, frame.stamp, t.x(), t.y(), t.z(),
                  q.w(), q.x(), q.y(), q.z(), frame.robot);
    const pqxx::result r = w.exec_params(kInsertPose, o.id, o.shape->name, o.parent, frame.stamp,
                                         t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
    ++(r.affected_rows() > 0 ? result.pose_rows : result.duplicate_rows);
  }
  if (result.pose_rows == 0 && result.duplicate_rows > 0) {
    result.duplicate = true;
    return result;  // rolled back: a replay must not move intervals or presence back in time
  }
  if (frame.complete)
    w.exec_params(
        "UPDATE instance SET present = false WHERE present AND NOT fixed AND robot = $2 AND "
        "last_seen < to_timestamp($1)",
        frame.stamp, frame.robot);
  if (frame.update_relations) {
    // In a subtransaction: when it fails (e.g. statement_timeout) the poses are still written.
    try {
      pqxx::subtransaction sub(w, "relations");
      sub.exec_params("SELECT semap_update_relations(to_timestamp($1), $2, $3, $4)", frame.stamp,
                      settings_.factor, settings_.on_max_distance, settings_.tolerance);
      sub.commit();
    } catch (const pqxx::sql_error& e) {
      if (std::string(e.sqlstate()).rfind("08", 0) == 0) throw;
      relation_error_ = e.what();
    }
  }
  w.commit();
  classes_written_.insert(new_classes.begin(), new_classes.end());
  return result;
}

void SemapDb::writeFixed(const std::vector<FixedObject>& objects) {
  pqxx::work w(impl_->conn);
  for (const FixedObject& o : objects) {
    const std::string class_name = "furniture:" + o.id;
    const Eigen::AlignedBox3d& b = o.box;
    w.exec_params(kUpsertClass, class_name, b.min().x(), b.min().y(), b.min().z(), b.max().x(),
                  b.max().y(), b.max().z(), "");
    const Eigen::Vector3d t = o.T_world_object.translation();
    const Eigen::Quaterniond q(o.T_world_object.rotation());
    w.exec_params(kUpsertFixed, o.id, class_name, t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
  }
  // now() is the transaction's start: what this call did not write is older.
  w.exec("UPDATE instance SET present = false WHERE fixed AND last_seen < now()");
  w.commit();
}

std::size_t SemapDb::pruneHistory(double before) {
  pqxx::work w(impl_->conn);
  std::size_t rows = 0;
  for (const char* sql :
       {"DELETE FROM pose_history WHERE stamp < to_timestamp($1)",
        "DELETE FROM relation_history WHERE until IS NOT NULL AND until < to_timestamp($1)",
        "DELETE FROM instance i WHERE NOT present AND last_seen < to_timestamp($1) AND NOT EXISTS "
        "(SELECT 1 FROM pose_history p WHERE p.instance_id = i.id)"})
    rows += w.exec_params(sql, before).affected_rows();
  w.commit();
  return rows;
}

std::vector<RelationRow> SemapDb::relations(const std::string& subject, const std::string& relation,
                                            const std::string& object, const std::string& mode) {
  checkRelationName(relation);
  pqxx::read_transaction w(impl_->conn);
  const pqxx::result r = w.exec_params(
      "SELECT subject, relation, object, extract(epoch FROM since)::float8 FROM "
      "semap_relations(NULLIF($1, ''), NULLIF($2, ''), NULLIF($3, ''), $4, $5, $6, $7)",
      subject, relation, object, checkedMode(mode), settings_.factor, settings_.on_max_distance,
      settings_.tolerance);
  std::vector<RelationRow> rows;
  for (const pqxx::row& row : r)
    rows.push_back({row[0].as<std::string>(), row[1].as<std::string>(), row[2].as<std::string>(),
                    optionalDouble(row[3])});
  return rows;
}

std::vector<std::string> SemapDb::objectsOn(const std::string& reference, const std::string& mode) {
  std::vector<std::string> ids;
  for (const RelationRow& r : relations("", "on", reference, mode)) ids.push_back(r.subject);
  return ids;
}

std::vector<std::string> SemapDb::objectsIn(const std::string& reference, const std::string& mode) {
  std::vector<std::string> ids;
  for (const RelationRow& r : relations("", "in", reference, mode)) ids.push_back(r.subject);
  return ids;
}

std::vector<std::string> SemapDb::directionalRelations(
    const std::string& a, const std::string& b, const std::string& mode,
    const std::optional<Eigen::Vector2d>& viewer) {
  if (a.empty() || b.empty())
    throw std::invalid_argument("directional relations need both objects");
  if (viewer && !viewer->allFinite()) throw std::invalid_argument("viewer position not finite");
  pqxx::read_transaction w(impl_->conn);
  const pqxx::result r =
      viewer ? w.exec_params("SELECT * FROM semap_viewer_relations($1, $2, $3, $4, $5, $6, $7, $8)",
                             a, b, checkedMode(mode), viewer->x(), viewer->y(), settings_.factor,
                             settings_.on_max_distance, settings_.tolerance)
             : w.exec_params(
                   "SELECT relation FROM semap_relations($1, NULL, $2, $3, $4, $5, $6) WHERE "
                   "relation NOT IN ('on', 'in')",
                   a, b, checkedMode(mode), settings_.factor, settings_.on_max_distance,
                   settings_.tolerance);
  std::vector<std::string> names;
  for (const pqxx::row& row : r) names.push_back(row[0].as<std::string>());
  return names;
}

std::optional<PoseAt> SemapDb::whereWas(const std::string& id, double stamp) {
  pqxx::read_transaction w(impl_->conn);
  const pqxx::result r = w.exec_params(
      "SELECT extract(epoch FROM stamp)::float8, parent, x, y, z, qw, qx, qy, qz "
      "FROM semap_where_was($1, to_timestamp($2))",
      id, stamp);
  if (r.empty()) return std::nullopt;
  return PoseAt{r[0][0].as<double>(), r[0][1].as<std::string>(), poseFrom(r[0], 2)};
}

SinceAnswer SemapDb::relationSince(const std::string& subject, const std::string& relation,
                                   const std::string& object, const std::string& mode) {
  if (subject.empty() || relation.empty() || object.empty())
    throw std::invalid_argument("relation since needs subject, relation and object");
  SinceAnswer a;
  for (const RelationRow& r : relations(subject, relation, object, mode))
    a.holds = true, a.since = r.since;
  return a;
}

std::vector<std::vector<std::string>> SemapDb::query(const std::string& sql) {
  pqxx::work w(impl_->conn);
  const pqxx::result r = w.exec(sql);
  w.commit();
  std::vector<std::vector<std::string>> rows;
  for (const pqxx::row& row : r) {
    rows.emplace_back();
    for (const pqxx::field& f : row) rows.back().push_back(f.is_null() ? "" : f.as<std::string>());
  }
  return rows;
}

}  // namespace sgt::semap
