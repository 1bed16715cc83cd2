// The SEMAP database (PostgreSQL + PostGIS + SFCGAL): object classes, instances, pose history and
// relation intervals, written and queried over one libpqxx connection. The schema and the SQL
// relation functions live in sql/semap_schema.sql and sql/semap_relations.sql; every answer here
// is one SQL call, so any SQL client can ask the same (e.g. SELECT * FROM semap_relations(...)).
// Not thread-safe: one SemapDb per thread. Connection errors surface as exceptions (pqxx::failure).
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace sgt::semap {

struct DbSettings {
  std::string host = "127.0.0.1";
  int port = 5433;
  std::string user = "semap_bridge";  // scripts/semap-db.sh's role for the bridge (no superuser)
  std::string password;               // empty: from passfile
  std::string passfile;  // libpq password file (0600), e.g. DIR/bridge.pgpass; empty: ~/.pgpass
  std::string dbname = "semap";
  int connect_timeout_s = 2;
  // A peer that stops answering (network stall, frozen server) is noticed within this: TCP
  // keepalives and tcp_user_timeout, so no call waits on a dead connection for minutes.
  int keepalive_idle_s = 5;
  double tcp_timeout_s = 10.0;
  double statement_timeout_s = 10.0;  // any one SQL statement; 0: none
  std::string
      sql_dir;  // where semap_schema.sql and semap_relations.sql are; empty: the package's sql/
  double factor = 3.5;  // relation parameters, as sgt::relations::RelationOptions
  double on_max_distance = 0.02;
  double tolerance = 0.0;  // m, containment: corners may lie this far outside
  std::string connectionString() const;
};

// An object class: its box in the object frame and a few mesh vertices for its hull.
struct ClassShape {
  std::string name;
  Eigen::AlignedBox3d box;
  std::vector<Eigen::Vector3d>
      hull_points;  // object frame; the stored hull is their 3D convex hull
};

struct InstancePose {
  std::string id;
  std::shared_ptr<const ClassShape> shape;
  std::string parent = "map";
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
};

// A fixed instance: a piece of the map's furniture (a table, shelf or cart top) that objects are
// on, in or beside. Stored with a class of its own ('furniture:' + id) holding its box.
struct FixedObject {
  std::string id;
  Eigen::AlignedBox3d box;  // in its own frame
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
};

// One scene-graph message: every object present at `stamp` (seconds). Instances missing from a
// complete frame are marked absent.
struct Frame {
  double stamp = 0.0;
  std::string robot;  // who wrote it; a complete frame marks only this robot's instances absent
  std::vector<InstancePose> objects;
  bool complete = true;
  bool update_relations = true;  // also record the relation intervals at this stamp
};

struct RelationRow {
  std::string subject, relation, object;
  std::optional<double> since;
};

struct PoseAt {
  double stamp = 0.0;
  std::string parent;
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
};

struct SinceAnswer {
  bool holds = false;
  std::optional<double> since;
};

class SemapDb {
 public:
  // Connects (throws pqxx::broken_connection when the server is unreachable).
  explicit SemapDb(DbSettings settings);
  ~SemapDb();
  SemapDb(const SemapDb&) = delete;
  SemapDb& operator=(const SemapDb&) = delete;

  bool isOpen() const;
  // Creates the extensions, tables and functions (idempotent).
  void installSchema();
  // One transaction: classes not written yet on this connection, instances, pose history rows and,
  // when asked, the relation intervals. Retrying a frame after an error writes nothing twice. A
  // frame whose every pose is stored already (a replayed stamp) is rolled back: `duplicate`.
  struct WriteResult {
    std::size_t pose_rows = 0, duplicate_rows = 0;
    bool duplicate = false;
  };
  WriteResult writeFrame(const Frame& frame);
  // One transaction: the fixed instances are exactly `objects` (present, not movable by frames);
  // fixed instances of an earlier call that are not among them are marked absent.
  void writeFixed(const std::vector<FixedObject>& objects);
  // Deletes history older than `before` (s): pose rows, relation intervals that ended, and absent
  // instances left without poses. Returns the rows deleted.
  std::size_t pruneHistory(double before);

  // Empty strings are "any"; mode "strict" or "relaxed" (empty: strict).
  std::vector<RelationRow> relations(const std::string& subject, const std::string& relation,
                                     const std::string& object, const std::string& mode);
  std::vector<std::string> objectsOn(const std::string& reference, const std::string& mode);
  std::vector<std::string> objectsIn(const std::string& reference, const std::string& mode);
  // In b's own frame, or with `viewer` (x, y in the world frame) as a person there looking at b
  // says it: left_of is the viewer's left (relations/spatial_relations.hpp, holdsFromViewpoint).
  std::vector<std::string> directionalRelations(
      const std::string& a, const std::string& b, const std::string& mode,
      const std::optional<Eigen::Vector2d>& viewer = std::nullopt);
  std::optional<PoseAt> whereWas(const std::string& id, double stamp);
  SinceAnswer relationSince(const std::string& subject, const std::string& relation,
                            const std::string& object, const std::string& mode);
  // Any SQL (tests, tools).
  std::vector<std::vector<std::string>> query(const std::string& sql);

  const DbSettings& settings() const { return settings_; }
  // Why the last frame's relation update failed (its poses were written); empty when it did not.
  const std::string& relationError() const { return relation_error_; }

 private:
  struct Impl;
  DbSettings settings_;
  std::unique_ptr<Impl> impl_;
  std::set<std::string> classes_written_;
  std::string relation_error_;
};

// "strict" for an empty mode; throws std::invalid_argument for anything but strict/relaxed.
std::string checkedMode(const std::string& mode);
// The relation names the SQL knows ("on", "in", "left_of", ...); throws for another non-empty one.
void checkRelationName(const std::string& relation);

}  // namespace sgt::semap
