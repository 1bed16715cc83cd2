// A throw-away PostgreSQL + PostGIS cluster for the SEMAP tests and benchmarks: a fresh temp
// directory (chowned to postgres when run as root), a free loopback port, started and stopped with
// scripts/semap-db.sh (so the tests use the same script as the launch files), removed at the end.
//   SGT_REQUIRE_POSTGRES();   // in a test: skips with a message when PostgreSQL/PostGIS are
//                             // missing; fails instead when SGT_REQUIRE_DB=1 (make test sets it)
//   sgt::test::PgServer pg;   // initdb + start + database "semap" with the schema
//   sgt::semap::SemapDb db(pg.settings());  // as the bridge's role (no superuser), SCRAM password
//   pg.freshDatabase();       // an empty copy with the schema, for one test
//   pg.superuser();           // connection settings of the superuser (fault injection)
#pragma once

#include <arpa/inet.h>
#include <glob.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <pqxx/pqxx>
#include <stdexcept>
#include <string>

#include "scene_graph_tracker/semap/db.hpp"

namespace sgt::test {

class PgServer {
 public:
  // Empty when the binaries are there; else why the database tests cannot run.
  static std::string missing() {
    if (!exists("/usr/lib/postgresql/*/bin/pg_ctl"))
      return "PostgreSQL binaries not found (postgresql-15)";
    if (!exists("/usr/share/postgresql/*/extension/postgis_sfcgal.control"))
      return "PostGIS with SFCGAL not found (postgresql-15-postgis-3)";
    if (getuid() == 0 && !exists("/usr/bin/su") && !exists("/bin/su"))
      return "running as root without su";
    return "";
  }

  // The cluster in a new directory under `parent` (e.g. a small file system, for a full disk).
  explicit PgServer(const std::string& parent = "/tmp") : port_(freePort()) {
    std::string tmpl = parent + "/sgt_pg_XXXXXX";
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("PgServer: mkdtemp failed in " + parent);
    dir_ = tmpl;
    start();
  }
  ~PgServer() {
    script("stop");
    std::system(("rm -rf '" + dir_ + "' 2>/dev/null || (sleep 1; rm -rf '" + dir_ + "')").c_str());
  }
  PgServer(const PgServer&) = delete;
  PgServer& operator=(const PgServer&) = delete;

  void start() {
    if (script("start") != 0)
      throw std::runtime_error("PgServer: could not start (see " + dir_ + "/script.log)");
  }
  void stop() {
    if (script("stop") != 0)
      throw std::runtime_error("PgServer: could not stop (see " + dir_ + "/script.log)");
  }

  // A new database with the schema and no data (a copy of "semap"), for one test.
  semap::DbSettings freshDatabase() {
    semap::DbSettings s = settings();
    s.dbname = "test_" + std::to_string(++databases_);
    pqxx::connection c(superuser().connectionString());
    pqxx::nontransaction(c).exec("CREATE DATABASE " + s.dbname + " TEMPLATE semap OWNER " + s.user);
    return s;
  }

  int port() const { return port_; }
  const std::string& dir() const { return dir_; }
  semap::DbSettings settings() const {
    semap::DbSettings s;
    s.port = port_, s.dbname = "semap", s.connect_timeout_s = 2;
    s.user = "semap_bridge", s.passfile = dir_ + "/bridge.pgpass";
    return s;
  }
  semap::DbSettings superuser() const {
    semap::DbSettings s = settings();
    s.user = "postgres", s.passfile = dir_ + "/superuser.pgpass", s.dbname = "postgres";
    return s;
  }

 private:
  static bool exists(const std::string& pattern) {
    glob_t g{};
    const bool found = glob(pattern.c_str(), 0, nullptr, &g) == 0 && g.gl_pathc > 0;
    globfree(&g);
    return found;
  }
  static int freePort() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET, a.sin_addr.s_addr = htonl(INADDR_LOOPBACK), a.sin_port = 0;
    socklen_t len = sizeof(a);
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0)
      throw std::runtime_error("PgServer: no free loopback port");
    close(fd);
    return ntohs(a.sin_port);
  }
  int script(const std::string& cmd) const {
    const std::string line = std::string(SGT_SOURCE_DIR) + "/scripts/semap-db.sh " + cmd + " '" +
                             dir_ + "' " + std::to_string(port_) + " semap >> '" + dir_ +
                             "/script.log' 2>&1";
    return std::system(line.c_str());
  }

  int port_;
  std::string dir_;
  int databases_ = 0;
};

}  // namespace sgt::test

// With SGT_REQUIRE_DB=1 a missing database fails the test: a skip would pass unnoticed.
#define SGT_REQUIRE_POSTGRES()                                                         \
  do {                                                                                 \
    const std::string why = ::sgt::test::PgServer::missing();                          \
    const char* required = std::getenv("SGT_REQUIRE_DB");                              \
    if (!why.empty() && required && std::string(required) == "1")                      \
      FAIL() << why << " (SGT_REQUIRE_DB=1: the SEMAP database tests must run)";       \
    if (!why.empty()) GTEST_SKIP() << why << ": the SEMAP database tests are skipped"; \
  } while (0)
