#pragma once
// HistoryWriter: the one writer thread of the history database. Producers
// (the real-time compensator loop, the temperature monitor) call Push*():
// lock-free, allocation-free, never waits for the disk. The thread drains the
// queue in batches and commits each batch in one transaction (WAL mode).
// When the queue is full the record is dropped and counted — a slow disk
// must never slow the machine's compensation.
//
//   HistoryWriter writer("machine.db");                       // creates/opens, starts the thread
//   writer.PushTemperature(t, "x_nut", raw, filtered, "ok");  // from the cycle
//   writer.Flush();                                           // e.g. before a query (not from the cycle)
//   writer.Stats().dropped                                    // report it
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "trueaxis/store/bounded_queue.hpp"
#include "trueaxis/store/history_record.hpp"
#include "trueaxis/store/history_sink.hpp"

namespace trueaxis::store {

struct HistoryWriterOptions {
  std::size_t queue_capacity = 16384;  // records (~300 bytes each); rounded up to a power of two
  std::size_t max_batch = 4096;        // records per transaction
  int idle_wait_ms = 50;               // how long the thread sleeps when the queue is empty
  bool IsValid(std::string* why) const;
};

struct HistoryWriterStats {
  std::uint64_t accepted = 0;      // pushed into the queue
  std::uint64_t dropped = 0;       // rejected because the queue was full
  std::uint64_t written = 0;       // committed to the database
  std::uint64_t failed = 0;        // lost because a write failed (see last_error)
  std::uint64_t batches = 0;
  std::string last_error;
  std::string BriefReport() const;
};

class HistorySink;

class HistoryWriter {
 public:
  // Opens (or creates) the database; throws InputError when it cannot.
  explicit HistoryWriter(const std::string& path, HistoryWriterOptions options = {});
  // Writes to any sink (a database server, a test double); takes ownership.
  explicit HistoryWriter(std::unique_ptr<HistorySink> sink, HistoryWriterOptions options = {});
  ~HistoryWriter();  // Close()
  HistoryWriter(const HistoryWriter&) = delete;
  HistoryWriter& operator=(const HistoryWriter&) = delete;

  bool Push(const HistoryRecord& record) noexcept;
  bool PushTemperature(double time_s, std::string_view channel, double raw_c, double filtered_c,
                       std::string_view status) noexcept;
  bool PushCompensation(double time_s, std::string_view axis, double position_mm, double correction_um,
                        std::string_view state) noexcept;
  bool PushAlarm(double time_s, std::string_view severity, std::string_view source, std::string_view message) noexcept;
  bool PushModelChange(double time_s, std::string_view sha256, std::string_view revision, std::string_view note) noexcept;

  // Blocks until every record accepted before the call is committed (or failed).
  void Flush();
  // Drains the queue, commits, stops the thread. Idempotent.
  void Close();
  HistoryWriterStats Stats() const;
  const std::string& path() const { return path_; }

 private:
  void Run();

  std::string path_;
  HistoryWriterOptions options_;
  std::unique_ptr<HistorySink> db_;
  BoundedQueue<HistoryRecord> queue_;
  std::atomic<std::uint64_t> accepted_{0}, dropped_{0}, written_{0}, failed_{0}, batches_{0};
  std::atomic<bool> stop_{false};
  std::atomic<bool> flush_wanted_{false};
  mutable std::mutex mutex_;  // guards last_error_ and the condition variables' waits
  std::condition_variable wake_;
  std::condition_variable progress_;
  std::string last_error_;
  std::thread thread_;
};

}  // namespace trueaxis::store
