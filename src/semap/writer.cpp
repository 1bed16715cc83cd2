#include "scene_graph_tracker/semap/writer.hpp"

#include <ros/console.h>
#include <ros/init.h>
#include <ros/time.h>

#include <pqxx/except>

namespace sgt::semap {
namespace {

// Errors that mean "the connection or the server", not "this frame": retry after reconnecting.
bool connectionError(const pqxx::sql_error& e) {
  const std::string state = e.sqlstate();
  // 08: connection exception; 57P0x: server shutting down / restarting; 53: out of resources;
  // 40001, 40P01: serialization failure, deadlock. Not 57014 (statement timeout): that frame is
  // rejected.
  return state.empty() || state.rfind("08", 0) == 0 || state.rfind("57P", 0) == 0 ||
         state.rfind("53", 0) == 0 || state == "40001" || state == "40P01";
}

}  // namespace

SemapWriter::SemapWriter(DbSettings settings, WriterOptions options)
    : settings_(std::move(settings)), options_(options), backoff_s_(options.backoff_min_s) {
  if (!::ros::isInitialized())
    ::ros::Time::init();  // outside a node (tests): the throttled logs use wall time
  thread_ = std::thread([this] { run(); });
}

SemapWriter::~SemapWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void SemapWriter::push(Frame frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The frame being written (the front while busy_) is never dropped: it is counted once, as
    // written or rejected.
    const std::size_t keep = busy_ ? 1 : 0,
                      capacity = std::max<std::size_t>(options_.queue_size, 1);
    while (queue_.size() > keep && queue_.size() - keep >= capacity) {
      queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(keep));
      ++stats_.dropped;
      ROS_WARN_THROTTLE(
          2.0,
          "semap: write queue full (%zu frames, database unreachable or slow): dropping the "
          "oldest frame (%zu dropped so far)",
          options_.queue_size, stats_.dropped);
    }
    queue_.push_back({next_seq_++, std::move(frame)});
    ++stats_.pushed;
    stats_.pending = queue_.size();
    stats_.max_pending = std::max(stats_.max_pending, stats_.pending);
  }
  changed_.notify_all();
}

WriterStats SemapWriter::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

bool SemapWriter::waitIdle(double timeout_s) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                           [this] { return queue_.empty() && !busy_; });
}

bool SemapWriter::connect() {
  try {
    auto db = std::make_unique<SemapDb>(settings_);
    db->installSchema();
    if (!options_.fixed_objects.empty()) db->writeFixed(options_.fixed_objects);
    db_ = std::move(db);
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.failed_attempts;
    ROS_WARN_THROTTLE(
        5.0, "semap: cannot connect to %s:%d/%s (%s); %zu frames queued, retrying in %.1f s",
        settings_.host.c_str(), settings_.port, settings_.dbname.c_str(), e.what(), queue_.size(),
        backoff_s_);
    return false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.connects, stats_.connected = true;
  backoff_s_ = options_.backoff_min_s;
  if (outage_since_) {
    stats_.last_outage_s = std::chrono::duration<double>(Clock::now() - *outage_since_).count();
    ROS_WARN("semap: %s %s:%d/%s after %.2f s; writing %zu queued frames",
             stats_.connects > 1 ? "reconnected to" : "connected to", settings_.host.c_str(),
             settings_.port, settings_.dbname.c_str(), stats_.last_outage_s, queue_.size());
    outage_since_.reset();
  } else {
    ROS_INFO("semap: connected to %s:%d/%s", settings_.host.c_str(), settings_.port,
             settings_.dbname.c_str());
  }
  return true;
}

void SemapWriter::sleepBackoff(std::unique_lock<std::mutex>& lock, Clock::time_point deadline) {
  auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(backoff_s_));
  if (stop_) until = std::min(until, deadline);
  const bool stopping = stop_;
  changed_.wait_until(lock, until, [&] { return stop_ != stopping; });
  backoff_s_ = std::min(2.0 * backoff_s_, options_.backoff_max_s);
}

SemapWriter::Outcome SemapWriter::write(const Item& item, std::string& error) {
  const Frame& frame = item.frame;
  if (!db_ && !connect()) return Outcome::kFailed;
  try {
    const SemapDb::WriteResult r = db_->writeFrame(frame);
    if (!db_->relationError().empty())
      ROS_WARN_THROTTLE(5.0, "semap: relation intervals not updated at %.3f (poses written): %s",
                        frame.stamp, db_->relationError().c_str());
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.duplicate_rows += r.duplicate ? 0 : r.duplicate_rows;
    stats_.pose_rows += r.duplicate ? 0 : r.pose_rows;
    // Stored already after a failed attempt: that commit went through before the connection broke
    // (pqxx::in_doubt_error), so the frame is written, once.
    if (!r.duplicate || item.attempted) return Outcome::kWritten;
    ++stats_.duplicate_frames;
    error = "every pose of it is stored already (a replayed stamp)";
    return Outcome::kRejected;
  } catch (const pqxx::sql_error& e) {
    error = e.what();
    return connectionError(e) || !db_->isOpen() ? Outcome::kFailed : Outcome::kRejected;
  } catch (const std::exception& e) {  // broken_connection, in_doubt_error, ...
    error = e.what();
    return Outcome::kFailed;
  }
}

void SemapWriter::prune(double newest_stamp) {
  if (options_.history_retention_s <= 0.0 || !db_) return;
  if (last_prune_ && newest_stamp >= *last_prune_ &&
      newest_stamp - *last_prune_ < options_.prune_period_s)
    return;
  last_prune_ = newest_stamp;
  try {
    const std::size_t rows = db_->pruneHistory(newest_stamp - options_.history_retention_s);
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.pruned_rows += rows;
  } catch (const std::exception& e) {  // the next write finds out whether the connection is gone
    ROS_WARN_THROTTLE(10.0, "semap: pruning the history failed: %s", e.what());
  }
}

void SemapWriter::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  Clock::time_point deadline = Clock::time_point::max();
  for (;;) {
    changed_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (stop_ && deadline == Clock::time_point::max())
      deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(options_.flush_timeout_s));
    if (queue_.empty() || (stop_ && Clock::now() >= deadline)) {
      if (!queue_.empty())
        ROS_ERROR("semap: stopping with %zu frames not written (database unreachable)",
                  queue_.size());
      if (stop_) return;
      continue;
    }
    const Item item = queue_.front();
    busy_ = true;
    lock.unlock();
    std::string error;
    const Outcome outcome = write(item, error);
    if (outcome == Outcome::kWritten) prune(item.frame.stamp);
    lock.lock();
    busy_ = false;
    if (outcome != Outcome::kFailed) {
      if (!queue_.empty() && queue_.front().seq == item.seq)
        queue_.pop_front();  // unless dropped meanwhile
      ++(outcome == Outcome::kWritten ? stats_.written : stats_.rejected);
      if (outcome == Outcome::kRejected)
        ROS_ERROR_THROTTLE(2.0, "semap: the frame at %.3f is not stored (%zu so far): %s",
                           item.frame.stamp, stats_.rejected, error.c_str());
      stats_.pending = queue_.size();
      changed_.notify_all();
      continue;
    }
    if (!queue_.empty() && queue_.front().seq == item.seq) queue_.front().attempted = true;
    if (db_) {  // the write failed on the connection: drop it, keep the frame, reconnect
      ROS_WARN_THROTTLE(2.0,
                        "semap: write failed (%s); keeping %zu frames queued, retrying in %.1f s",
                        error.c_str(), queue_.size(), backoff_s_);
      db_.reset();
    }
    if (!outage_since_) outage_since_ = Clock::now();
    stats_.connected = false;
    changed_.notify_all();
    sleepBackoff(lock, deadline);
  }
}

}  // namespace sgt::semap
