// Writes frames into the SEMAP database from its own thread, through a bounded queue, so the
// caller never waits for the database. When the server is down or restarts, frames stay queued
// (warning, throttled), the writer reconnects with exponential backoff and writes the backlog in
// order. A full queue drops its oldest frame, with a warning that says so. A frame the server
// rejects for its content (not for the connection), or whose poses are all stored already (a
// replayed stamp), is logged and counted as rejected. Every failed attempt, whatever its kind
// (connection refused, server restarting, disk full), waits the backoff before the next one.
// At all times: pushed = written + dropped + rejected + pending.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "scene_graph_tracker/semap/db.hpp"

namespace sgt::semap {

struct WriterOptions {
  std::size_t queue_size = 2000;  // frames
  double backoff_min_s = 0.1;     // first reconnection delay, doubled up to backoff_max_s
  double backoff_max_s = 2.0;
  double flush_timeout_s = 3.0;      // on destruction: how long to keep writing the backlog
  double history_retention_s = 0.0;  // pose and relation history older than this (message time,
                                     // behind the newest frame) is deleted; 0: kept for ever
  double prune_period_s = 10.0;      // message time between prunings
  // The map's furniture, written at every connection (SemapDb::writeFixed); empty: the fixed
  // instances in the database are left as they are.
  std::vector<FixedObject> fixed_objects;
};

struct WriterStats {
  std::size_t pushed = 0, written = 0, dropped = 0, rejected = 0;
  std::size_t duplicate_frames = 0;  // of rejected: every pose stored already (replayed stamps)
  std::size_t duplicate_rows = 0;    // pose rows of written frames that were stored already
  std::size_t pose_rows = 0;         // pose history rows written (what the database must hold)
  std::size_t pruned_rows = 0;
  std::size_t pending = 0, max_pending = 0;  // queued frames now / at most
  std::size_t connects = 0, failed_attempts = 0;
  bool connected = false;
  double last_outage_s = 0.0;  // from the first failed write to the reconnection, last outage
};

class SemapWriter {
 public:
  SemapWriter(DbSettings settings, WriterOptions options = {});
  ~SemapWriter();  // writes what it can within flush_timeout_s, then stops
  SemapWriter(const SemapWriter&) = delete;
  SemapWriter& operator=(const SemapWriter&) = delete;

  void push(Frame frame);  // never blocks on the database
  WriterStats stats() const;
  // Until every pushed frame is written, dropped or rejected; false on timeout.
  bool waitIdle(double timeout_s) const;

 private:
  using Clock = std::chrono::steady_clock;
  void run();
  bool connect();
  void sleepBackoff(std::unique_lock<std::mutex>& lock, Clock::time_point deadline);
  struct Item {
    std::uint64_t seq;
    Frame frame;
    bool attempted = false;  // a write of it failed on the connection before
  };
  enum class Outcome { kWritten, kRejected, kFailed };
  Outcome write(const Item& item, std::string& error);  // writer thread, without the lock
  void prune(double newest_stamp);                      // writer thread, without the lock

  const DbSettings settings_;
  const WriterOptions options_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::deque<Item> queue_;
  std::uint64_t next_seq_ = 0;
  bool stop_ = false;
  bool busy_ = false;  // the writer holds a frame it has not finished
  WriterStats stats_;
  std::unique_ptr<SemapDb> db_;  // writer thread only
  double backoff_s_;
  std::optional<Clock::time_point> outage_since_;
  std::optional<double> last_prune_;  // message time of the last pruning
  std::thread thread_;
};

}  // namespace sgt::semap
