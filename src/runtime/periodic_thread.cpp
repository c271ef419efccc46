#include "trueaxis/runtime/periodic_thread.hpp"

namespace trueaxis::runtime {

PeriodicThread::PeriodicThread(double period_s, Clock::time_point epoch, std::function<void(double)> body)
    : period_s_(period_s), epoch_(epoch), body_(std::move(body)) {}

PeriodicThread::~PeriodicThread() { Stop(); }

void PeriodicThread::Start() {
  if (running_.exchange(true)) return;
  stop_.store(false);
  thread_ = std::thread([this] { Main(); });
}

void PeriodicThread::Stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mu_);
    stop_.store(true);
  }
  wake_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  running_.store(false);
}

void PeriodicThread::Account(double call_s, bool overrun) {
  calls_.fetch_add(1, std::memory_order_relaxed);
  if (overrun) overruns_.fetch_add(1, std::memory_order_relaxed);
  // single writer: plain load/store is enough
  if (call_s > max_call_s_.load(std::memory_order_relaxed)) max_call_s_.store(call_s, std::memory_order_relaxed);
  total_call_s_.store(total_call_s_.load(std::memory_order_relaxed) + call_s, std::memory_order_relaxed);
}

void PeriodicThread::Main() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_));
  auto deadline = Clock::now();
  while (!stop_.load(std::memory_order_relaxed)) {
    const auto start = Clock::now();
    body_(std::chrono::duration<double>(start - epoch_).count());
    const auto end = Clock::now();
    deadline += period;
    const bool overrun = end > deadline;
    if (overrun) deadline += ((end - deadline) / period + 1) * period;  // skip the missed deadlines
    Account(std::chrono::duration<double>(end - start).count(), overrun);
    std::unique_lock<std::mutex> lock(wake_mu_);  // outside the call: the call itself takes no lock
    wake_cv_.wait_until(lock, deadline, [this] { return stop_.load(std::memory_order_relaxed); });
  }
}

PeriodicStats PeriodicThread::Stats() const {
  PeriodicStats s;
  s.calls = calls_.load();
  s.overruns = overruns_.load();
  s.max_call_s = max_call_s_.load();
  s.mean_call_s = s.calls ? total_call_s_.load() / static_cast<double>(s.calls) : 0;
  return s;
}

}  // namespace trueaxis::runtime
