// The SEMAP writer against a fault matrix: a backend killed (kill -9) in the middle of its commits,
// statements that time out, a frozen server, a full disk, replayed stamps. After each, every
// pushed frame is accounted for: pushed = written + dropped + rejected, and the database holds
// exactly the written frames.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <pqxx/pqxx>
#include <thread>

#include "pg_server.hpp"
#include "writer_support.hpp"

namespace sgt {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// The pid of the server process that serves the writer's connection; waits up to 15 s for it
// (after a crash the server recovers first, then the writer reconnects). 0 when there is none.
int writerBackend(const test::PgServer& pg) {
  const auto until = Clock::now() + std::chrono::seconds(15);
  do {
    try {
      pqxx::connection c(pg.superuser().connectionString());
      const pqxx::result r = pqxx::nontransaction(c).exec(
          "SELECT pid FROM pg_stat_activity WHERE usename = 'semap_bridge' AND application_name = "
          "'scene_graph_tracker semap' ORDER BY backend_start DESC LIMIT 1");
      if (!r.empty()) return r[0][0].as<int>();
    } catch (const pqxx::broken_connection&) {  // recovering from the last kill
    }
    std::this_thread::sleep_for(milliseconds(50));
  } while (Clock::now() < until);
  return 0;
}

// Pushes frames first..first+count-1 at 50 Hz from its own thread; records the slowest push.
class Feeder {
 public:
  Feeder(semap::SemapWriter& w, int count, int first = 0)
      : thread_([this, &w, count, first] {
          const auto start = Clock::now();
          for (int i = 0; i < count; ++i) {
            std::this_thread::sleep_until(start + milliseconds(20 * i));
            const auto t0 = Clock::now();
            w.push(test::slidingFrame(first + i));
            slowest_s = std::max(slowest_s.load(),
                                 std::chrono::duration<double>(Clock::now() - t0).count());
          }
        }) {}
  ~Feeder() { join(); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  std::atomic<double> slowest_s{0.0};

 private:
  std::thread thread_;
};

// A connection to the store; after a killed backend the server may still be recovering (it
// refuses connections until then): retried for up to 30 s.
std::unique_ptr<semap::SemapDb> connectWhenReady(const test::PgServer& pg) {
  const auto until = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    try {
      return std::make_unique<semap::SemapDb>(pg.settings());
    } catch (const pqxx::broken_connection&) {
      if (Clock::now() > until) throw;
      std::this_thread::sleep_for(milliseconds(100));
    }
  }
}

// Every frame is written, dropped or rejected, and the database holds exactly the written ones.
void expectAccounted(const semap::SemapWriter& writer, const test::PgServer& pg,
                     std::size_t pushed) {
  ASSERT_TRUE(writer.waitIdle(60.0)) << writer.stats().pending << " frames still queued";
  const semap::WriterStats s = writer.stats();
  EXPECT_EQ(s.pushed, pushed);
  EXPECT_EQ(s.pushed, s.written + s.dropped + s.rejected);
  const std::unique_ptr<semap::SemapDb> db = connectWhenReady(pg);
  EXPECT_EQ(db->query("SELECT count(DISTINCT stamp) FROM pose_history")[0][0],
            std::to_string(s.written));
  EXPECT_EQ(db->query("SELECT count(*) FROM pose_history")[0][0], std::to_string(3 * s.written));
  std::printf(
      "[ semap faults ] pushed %zu: written %zu, dropped %zu, rejected %zu (%zu replayed); "
      "%zu connections, %zu failed attempts\n",
      s.pushed, s.written, s.dropped, s.rejected, s.duplicate_frames, s.connects,
      s.failed_attempts);
}

TEST(SemapFaults, BackendKilledMidCommitLosesNothing) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::SemapWriter writer(pg.settings(), test::fastRetry(5000));
  constexpr int kFrames = 250;
  {
    Feeder feeder(writer, kFrames);
    for (int kill_no = 0; kill_no < 3; ++kill_no) {
      // Each kill hits an established connection (one that is still connecting would fail and
      // be retried without counting as a connect): wait for the writer's reconnect first.
      const auto until = Clock::now() + std::chrono::seconds(30);
      while (writer.stats().connects < static_cast<std::size_t>(kill_no) + 1 &&
             Clock::now() < until)
        std::this_thread::sleep_for(milliseconds(20));
      std::this_thread::sleep_for(milliseconds(600));  // frames in flight
      const int pid = writerBackend(pg);
      ASSERT_GT(pid, 0) << "no backend serves the writer";
      ASSERT_EQ(::kill(pid, SIGKILL), 0);  // the postmaster then restarts every backend
    }
  }
  // Frames after the last kill, which only a new connection writes (on a slow machine the kills
  // can outlast the first frames).
  constexpr int kAfter = 25;
  Feeder(writer, kAfter, kFrames).join();
  expectAccounted(writer, pg, kFrames + kAfter);
  const semap::WriterStats s = writer.stats();
  EXPECT_EQ(s.written, static_cast<std::size_t>(kFrames + kAfter)) << "a killed commit is retried";
  EXPECT_GE(s.connects, 4u);
}

TEST(SemapFaults, StatementTimeoutsRejectFramesAndCountThem) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::DbSettings settings = pg.settings();
  settings.statement_timeout_s = 0.2;
  semap::SemapWriter writer(settings, test::fastRetry(5000));
  constexpr int kFrames = 150;
  {
    Feeder feeder(writer, kFrames);
    std::this_thread::sleep_for(milliseconds(800));
    semap::DbSettings admin = pg.superuser();
    admin.dbname = "semap";
    pqxx::connection c(admin.connectionString());
    pqxx::work lock(c);
    lock.exec("LOCK TABLE pose_history IN ACCESS EXCLUSIVE MODE");
    std::this_thread::sleep_for(milliseconds(1200));  // every write meanwhile times out
    lock.commit();
  }
  expectAccounted(writer, pg, kFrames);
  const semap::WriterStats s = writer.stats();
  EXPECT_GT(s.rejected, 0u);
  EXPECT_GT(s.written, 50u);
  EXPECT_EQ(s.dropped, 0u);
}

TEST(SemapFaults, AFrozenServerNeverBlocksThePusher) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::SemapWriter writer(pg.settings(), test::fastRetry(5000));
  constexpr int kFrames = 200;
  std::unique_ptr<Feeder> feeder = std::make_unique<Feeder>(writer, kFrames);
  std::this_thread::sleep_for(milliseconds(1000));
  const int pid = writerBackend(pg);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGSTOP), 0);  // the backend hangs mid-statement, the socket stays open
  std::this_thread::sleep_for(milliseconds(2000));
  const semap::WriterStats frozen = writer.stats();
  ASSERT_EQ(::kill(pid, SIGCONT), 0);
  feeder->join();
  EXPECT_GT(frozen.pending, 50u) << "frames queue while the server does not answer";
  EXPECT_LT(feeder->slowest_s.load(), 0.05) << "push() waited for the database";
  expectAccounted(writer, pg, kFrames);
  EXPECT_EQ(writer.stats().written, static_cast<std::size_t>(kFrames));
}

TEST(SemapFaults, ReplayedStampsAreRejectedNotCountedAsWritten) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::SemapWriter writer(pg.settings(), test::fastRetry(5000));
  for (int pass = 0; pass < 2; ++pass)  // a bag played twice
    for (int i = 0; i < 20; ++i) writer.push(test::slidingFrame(i));
  expectAccounted(writer, pg, 40);
  const semap::WriterStats s = writer.stats();
  EXPECT_EQ(s.written, 20u);
  EXPECT_EQ(s.rejected, 20u);
  EXPECT_EQ(s.duplicate_frames, 20u);
}

TEST(SemapFaults, HistoryOlderThanTheRetentionIsPruned) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::WriterOptions options = test::fastRetry(5000);
  options.history_retention_s = 1.0, options.prune_period_s = 0.2;
  semap::SemapWriter writer(pg.settings(), options);
  constexpr int kFrames = 200;  // 4 s of message time
  for (int i = 0; i < kFrames; ++i) writer.push(test::slidingFrame(i));
  ASSERT_TRUE(writer.waitIdle(60.0));
  const semap::WriterStats s = writer.stats();
  EXPECT_EQ(s.written, static_cast<std::size_t>(kFrames));
  EXPECT_GT(s.pruned_rows, 0u);
  semap::SemapDb db(pg.settings());
  const double newest = test::slidingFrame(kFrames - 1).stamp;
  const double oldest =
      std::stod(db.query("SELECT extract(epoch FROM min(stamp))::float8 FROM pose_history")[0][0]);
  EXPECT_GE(oldest, newest - 1.0 - 0.2 - 1e-6);  // retention plus at most one prune period
  EXPECT_LE(oldest, newest - 1.0 + 1e-6);
  EXPECT_EQ(db.query("SELECT count(*) FROM instance")[0][0], "3");  // present ones are kept
}

// A small file system of its own (tmpfs), filled up while frames come in: writes fail (disk full,
// perhaps a server restart on a WAL write), the writer backs off instead of spinning, keeps the
// frames and writes them once there is space again.
TEST(SemapFaults, FullDiskBacksOffAndWritesTheBacklogLater) {
  SGT_REQUIRE_POSTGRES();
  const std::filesystem::path mnt =
      std::filesystem::temp_directory_path() / ("sgt_full_disk_" + std::to_string(::getpid()));
  std::filesystem::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=160m,mode=0755") != 0) {
    std::filesystem::remove(mnt);
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): the full-disk case is skipped";
  }
  struct Unmount {
    std::filesystem::path p;
    ~Unmount() {
      ::umount2(p.c_str(), MNT_DETACH);
      std::filesystem::remove(p);
    }
  } unmount{mnt};
  auto pg = std::make_unique<test::PgServer>(mnt.string());
  semap::SemapWriter writer(pg->settings(), test::fastRetry(5000));
  for (int i = 0; i < 10; ++i) writer.push(test::slidingFrame(i));
  ASSERT_TRUE(writer.waitIdle(30.0));
  const std::string filler = (mnt / "filler").string();
  std::system(("dd if=/dev/zero of='" + filler + "' bs=1M 2>/dev/null; sync").c_str());
  const auto full_since = Clock::now();
  for (int i = 10; i < 110; ++i) {
    writer.push(test::slidingFrame(i));
    std::this_thread::sleep_for(milliseconds(20));
  }
  std::this_thread::sleep_for(milliseconds(1000));
  const semap::WriterStats full = writer.stats();
  const double full_s = std::chrono::duration<double>(Clock::now() - full_since).count();
  std::filesystem::remove(filler);
  expectAccounted(writer, *pg, 110);
  const semap::WriterStats s = writer.stats();
  EXPECT_GT(full.pending, 0u) << "writes should fail while the disk is full";
  // Backoff: at most one attempt per backoff_min_s (plus reconnections), not a tight loop.
  EXPECT_LT(full.failed_attempts + full.connects, static_cast<std::size_t>(full_s / 0.05) + 5);
  EXPECT_EQ(s.written + s.rejected, 110u);
  EXPECT_GE(s.written, 100u);
  pg.reset();
}

}  // namespace
}  // namespace sgt
