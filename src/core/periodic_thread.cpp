#include "trueaxis/core/periodic_thread.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::core {

PeriodicThread::PeriodicThread(double period_s, Clock::time_point epoch, std::function<void(double)> body)
    : period_s_(period_s), epoch_(epoch), body_(std::move(body)) {}

PeriodicThread::~PeriodicThread() { Stop(); }

void PeriodicThread::Start() {
  if (running_.exchange(true)) return;
  {
    std::lock_guard<std::mutex> lock(wake_mu_);
    stop_ = false;
    woken_ = false;
  }
  thread_ = std::thread([this] { Main(); });
}

void PeriodicThread::Start(double period_s, std::function<void(double)> body) {
  Stop();
  period_s_ = period_s;
  epoch_ = Clock::now();
  body_ = std::move(body);
  Start();
}

void PeriodicThread::Stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mu_);
    stop_ = true;
  }
  wake_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  running_.store(false);
}

void PeriodicThread::Wake() {
  {
    std::lock_guard<std::mutex> lock(wake_mu_);
    woken_ = true;
  }
  wake_cv_.notify_all();
}

namespace {
constexpr double kHistogramFloorS = 1e-7;
}  // namespace

void PeriodicThread::Account(double call_s, bool overrun) {
  const std::uint64_t number = calls_.fetch_add(1, std::memory_order_relaxed) + 1;
  if (overrun) overruns_.fetch_add(1, std::memory_order_relaxed);
  if (call_s > period_s_) long_calls_.fetch_add(1, std::memory_order_relaxed);
  const double decades = call_s > kHistogramFloorS ? std::log10(call_s / kHistogramFloorS) : 0.0;
  const int bin = std::clamp(static_cast<int>(decades * kBinsPerDecade), 0, kBins - 1);
  histogram_[static_cast<std::size_t>(bin)].fetch_add(1, std::memory_order_relaxed);
  // single writer: plain load/store is enough
  if (call_s > max_call_s_.load(std::memory_order_relaxed)) {
    max_call_s_.store(call_s, std::memory_order_relaxed);
    max_call_number_.store(number, std::memory_order_relaxed);
  }
  total_call_s_.store(total_call_s_.load(std::memory_order_relaxed) + call_s, std::memory_order_relaxed);
}

void PeriodicThread::Main() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_));
  auto deadline = Clock::now();  // the first call at once
  std::unique_lock<std::mutex> lock(wake_mu_);
  while (!stop_) {
    woken_ = false;
    lock.unlock();  // the call itself takes no lock
    const auto start = Clock::now();
    body_(std::chrono::duration<double>(start - epoch_).count());
    const auto end = Clock::now();
    if (start >= deadline) deadline += period;  // a call on the grid (a woken one ahead of it leaves the grid)
    const bool overrun = end > deadline;
    if (overrun) deadline += ((end - deadline) / period + 1) * period;  // skip the missed deadlines
    Account(std::chrono::duration<double>(end - start).count(), overrun);
    lock.lock();
    wake_cv_.wait_until(lock, deadline, [this] { return stop_ || woken_; });
  }
}

PeriodicStats PeriodicThread::Stats() const {
  PeriodicStats s;
  s.calls = calls_.load();
  s.overruns = overruns_.load();
  s.max_call_s = max_call_s_.load();
  s.mean_call_s = s.calls ? total_call_s_.load() / static_cast<double>(s.calls) : 0;
  s.max_call_number = max_call_number_.load();
  s.long_calls = long_calls_.load();
  // Percentiles: the upper edge of the bin holding the q-th call, never above the longest call.
  std::array<std::uint64_t, kBins> counts;
  std::uint64_t total = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) total += counts[b] = histogram_[b].load(std::memory_order_relaxed);
  auto percentile = [&](double q) {
    if (total == 0) return 0.0;
    const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total)));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < counts.size(); ++b) {
      seen += counts[b];
      if (seen >= rank)
        return std::min(s.max_call_s, kHistogramFloorS * std::pow(10.0, static_cast<double>(b + 1) / kBinsPerDecade));
    }
    return s.max_call_s;
  };
  s.p50_call_s = percentile(0.5);
  s.p99_call_s = percentile(0.99);
  return s;
}

}  // namespace trueaxis::core
