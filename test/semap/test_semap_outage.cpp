// The SEMAP writer survives the database going away: frames pushed while the server is stopped
// (pg_ctl stop, mid-run) stay queued, the writer reconnects when it is back and writes the backlog
// in order; nothing is lost. A full queue drops its oldest frames and says so.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "pg_server.hpp"
#include "scene_graph_tracker/semap/writer.hpp"
#include "writer_support.hpp"

namespace sgt {
namespace {

using Clock = std::chrono::steady_clock;

using test::arrivedStamps;
using test::fastRetry;
semap::Frame frame(int i) { return test::slidingFrame(i); }

TEST(SemapOutage, ServerStoppedAndRestartedMidRunLosesNothing) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::SemapWriter writer(pg.settings(), fastRetry(5000));
  constexpr int kFrames = 300;  // 6 s at 50 Hz
  std::atomic<int> pushed{0};
  std::thread feeder([&] {
    const auto start = Clock::now();
    for (int i = 0; i < kFrames; ++i) {
      std::this_thread::sleep_until(start + std::chrono::milliseconds(20 * i));
      writer.push(frame(i));
      pushed = i + 1;
    }
  });
  // Joined on every way out (a failing pg.stop()/start() throws): never destroyed joinable.
  struct Joiner {
    std::thread& t;
    ~Joiner() {
      if (t.joinable()) t.join();
    }
  } joiner{feeder};
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto before = writer.stats();
  pg.stop();  // pg_ctl stop -m fast while frames keep coming
  const int pushed_at_stop = pushed;
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  const auto down = writer.stats();
  pg.start();
  const auto restarted = Clock::now();
  while (writer.stats().connects < 2 && Clock::now() - restarted < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const double reconnect_s = std::chrono::duration<double>(Clock::now() - restarted).count();
  feeder.join();
  ASSERT_TRUE(writer.waitIdle(30.0)) << writer.stats().pending << " frames still queued";
  const auto s = writer.stats();

  EXPECT_GT(before.written, 0u);
  EXPECT_FALSE(down.connected);
  EXPECT_GT(down.pending, 50u) << "frames should queue while the server is down";
  EXPECT_EQ(s.pushed, static_cast<std::size_t>(kFrames));
  EXPECT_EQ(s.written, static_cast<std::size_t>(kFrames));
  EXPECT_EQ(s.dropped, 0u);
  EXPECT_EQ(s.rejected, 0u);
  EXPECT_EQ(s.connects, 2u);
  EXPECT_LT(reconnect_s, 1.5);

  semap::SemapDb db(pg.settings());
  std::vector<double> expected;
  for (int i = 0; i < kFrames; ++i) expected.push_back(frame(i).stamp);
  for (const char* id : {"table_1", "box_1", "box_2"}) {
    const auto stamps = arrivedStamps(db, id);
    ASSERT_EQ(stamps.size(), expected.size()) << id;
    for (std::size_t i = 0; i < stamps.size(); ++i)
      ASSERT_NEAR(stamps[i], expected[i], 1e-5) << id << " row " << i;
  }
  EXPECT_EQ(
      db.query("SELECT count(*) FROM relation_history WHERE subject = 'box_1' AND relation = 'on' "
               "AND object = 'table_1' AND mode = 'strict'")[0][0],
      "1");
  std::printf(
      "[ semap outage ] %d frames (%d rows); server stopped after %d frames for 2.0 s; %zu frames "
      "queued at "
      "most; reconnected %.3f s after the restart (outage %.2f s); %zu written, %zu dropped, %u "
      "lost\n",
      kFrames, 3 * kFrames, pushed_at_stop, s.max_pending, reconnect_s, s.last_outage_s, s.written,
      s.dropped, 0u);
}

TEST(SemapOutage, FullQueueDropsTheOldestAndKeepsTheNewest) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  semap::SemapWriter writer(pg.settings(), fastRetry(20));
  writer.push(frame(0));
  ASSERT_TRUE(writer.waitIdle(10.0));
  pg.stop();
  for (int i = 1; i <= 50; ++i) writer.push(frame(i));
  // The newest 20 stay queued. Frame 1 stays too when the writer was in the middle of trying it
  // as the queue filled (a frame being written is never dropped): that depends on the timing.
  const semap::WriterStats down = writer.stats();
  const bool in_flight_kept = down.pending == 21u;
  EXPECT_TRUE(down.pending == 20u || in_flight_kept) << down.pending;
  EXPECT_EQ(down.dropped + down.pending, 50u);
  pg.start();
  ASSERT_TRUE(writer.waitIdle(20.0));
  EXPECT_EQ(writer.stats().written, 1u + down.pending);
  semap::SemapDb db(pg.settings());
  std::vector<double> expected = {frame(0).stamp};
  if (in_flight_kept) expected.push_back(frame(1).stamp);
  for (int i = 31; i <= 50; ++i) expected.push_back(frame(i).stamp);
  const auto stamps = arrivedStamps(db, "box_1");
  ASSERT_EQ(stamps.size(), expected.size());
  for (std::size_t i = 0; i < stamps.size(); ++i) EXPECT_NEAR(stamps[i], expected[i], 1e-5);
}

TEST(SemapOutage, WriterStartsBeforeTheServerAndConnectsLater) {
  SGT_REQUIRE_POSTGRES();
  test::PgServer pg;
  pg.stop();
  semap::SemapWriter writer(pg.settings(), fastRetry(100));
  for (int i = 0; i < 10; ++i) writer.push(frame(i));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(writer.stats().connected);
  EXPECT_GT(writer.stats().failed_attempts, 0u);
  pg.start();
  ASSERT_TRUE(writer.waitIdle(20.0));
  EXPECT_EQ(writer.stats().written, 10u);
}

}  // namespace
}  // namespace sgt
