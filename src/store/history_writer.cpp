#include "trueaxis/store/history_writer.hpp"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {

bool HistoryWriterOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (queue_capacity < 2 || queue_capacity > (std::size_t{1} << 24)) return fail("queue_capacity must be 2 .. 16777216");
  if (max_batch < 1) return fail("max_batch must be >= 1");
  if (idle_wait_ms < 1 || idle_wait_ms > 10000) return fail("idle_wait_ms must be 1 .. 10000");
  return true;
}

std::string HistoryWriterStats::BriefReport() const {
  std::string s = fmt::format("history: {} accepted, {} written in {} batches, {} dropped (queue full), {} failed",
                              accepted, written, batches, dropped, failed);
  if (!last_error.empty()) s += "; last error: " + last_error;
  return s;
}

namespace {
HistoryWriterOptions Checked(HistoryWriterOptions o) {
  std::string why;
  if (!o.IsValid(&why)) throw std::invalid_argument("HistoryWriter options: " + why);
  return o;
}
}  // namespace

HistoryWriter::HistoryWriter(const std::string& path, HistoryWriterOptions options)
    : HistoryWriter(std::make_unique<HistoryDb>(path, HistoryDb::Mode::kReadWrite), options) {}

HistoryWriter::HistoryWriter(std::unique_ptr<HistorySink> sink, HistoryWriterOptions options)
    : path_(sink ? sink->Describe() : std::string()), options_(Checked(options)), db_(std::move(sink)),
      queue_(options_.queue_capacity) {
  if (!db_) throw std::invalid_argument("HistoryWriter: no sink");
  thread_ = std::thread([this] { Run(); });
}

HistoryWriter::~HistoryWriter() { Close(); }

bool HistoryWriter::Push(const HistoryRecord& record) noexcept {
  if (queue_.TryPush(record)) {
    accepted_.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool HistoryWriter::PushTemperature(double time_s, std::string_view channel, double raw_c, double filtered_c,
                                    std::string_view status) noexcept {
  return Push(HistoryRecord::Temperature(time_s, channel, raw_c, filtered_c, status));
}
bool HistoryWriter::PushCompensation(double time_s, std::string_view axis, double position_mm, double correction_um,
                                     std::string_view state) noexcept {
  return Push(HistoryRecord::Compensation(time_s, axis, position_mm, correction_um, state));
}
bool HistoryWriter::PushAlarm(double time_s, std::string_view severity, std::string_view source,
                              std::string_view message) noexcept {
  return Push(HistoryRecord::Alarm(time_s, severity, source, message));
}
bool HistoryWriter::PushModelChange(double time_s, std::string_view sha256, std::string_view revision,
                                    std::string_view note) noexcept {
  return Push(HistoryRecord::ModelChange(time_s, sha256, revision, note));
}

void HistoryWriter::Run() {
  std::vector<HistoryRecord> batch;
  batch.reserve(options_.max_batch);
  bool have_carry = false;
  HistoryRecord carry;
  for (;;) {
    batch.clear();
    if (have_carry) {
      batch.push_back(carry);
      have_carry = false;
    }
    HistoryRecord r;
    while (batch.size() < options_.max_batch && queue_.TryPop(r)) batch.push_back(r);
    if (!batch.empty()) {
      try {
        db_->InsertBatch(batch);
        written_.fetch_add(batch.size(), std::memory_order_relaxed);
      } catch (const std::exception& e) {
        // The records of this batch are lost, but the writer keeps going:
        // a full disk may recover, and the loop must never stop for us.
        failed_.fetch_add(batch.size(), std::memory_order_relaxed);
        std::lock_guard lock(mutex_);
        last_error_ = e.what();
      }
      batches_.fetch_add(1, std::memory_order_relaxed);
      progress_.notify_all();
      continue;  // drain as fast as the disk allows
    }
    if (stop_.load(std::memory_order_acquire)) {
      // One last look: a producer may have pushed between the pop and the flag.
      if (queue_.TryPop(carry)) {
        have_carry = true;
        continue;
      }
      break;
    }
    progress_.notify_all();
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, std::chrono::milliseconds(options_.idle_wait_ms),
                   [this] { return flush_wanted_.load() || stop_.load(); });
    flush_wanted_.store(false);
  }
  progress_.notify_all();
}

void HistoryWriter::Flush() {
  const std::uint64_t target = accepted_.load(std::memory_order_acquire);
  std::unique_lock lock(mutex_);
  while (written_.load() + failed_.load() < target && thread_.joinable()) {
    flush_wanted_.store(true);
    wake_.notify_all();
    progress_.wait_for(lock, std::chrono::milliseconds(20));
  }
}

void HistoryWriter::Close() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_release);
  {
    std::lock_guard lock(mutex_);
    wake_.notify_all();
  }
  thread_.join();
  db_.reset();
}

HistoryWriterStats HistoryWriter::Stats() const {
  HistoryWriterStats s;
  s.accepted = accepted_.load();
  s.dropped = dropped_.load();
  s.written = written_.load();
  s.failed = failed_.load();
  s.batches = batches_.load();
  std::lock_guard lock(mutex_);
  s.last_error = last_error_;
  return s;
}

}  // namespace trueaxis::store
