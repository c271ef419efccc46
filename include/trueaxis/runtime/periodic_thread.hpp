#pragma once
// PeriodicThread: calls a function every `period_s` on its own thread, on
// absolute deadlines of the steady clock. A call finishing after the next
// deadline is an overrun, counted; missed deadlines are skipped (the next call
// starts on the period grid after now), never caught up in a burst. Stop()
// wakes the thread at once (a 10 s period never delays SIGINT).
//
// The real-time loop and each I/O worker (LoopRunner) are one PeriodicThread
// each, all timed from one epoch, so their timestamps are comparable. The
// thread itself allocates nothing once started.
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

namespace trueaxis::runtime {

struct PeriodicStats {
  std::uint64_t calls = 0;
  std::uint64_t overruns = 0;
  double max_call_s = 0;   // longest call
  double mean_call_s = 0;
  // Median and 99th percentile of the call durations, from a histogram of 20 bins per decade
  // (0.1 µs … 10 s): each the upper edge of its bin, so at most 12 % above the exact value.
  double p50_call_s = 0, p99_call_s = 0;
  std::uint64_t max_call_number = 0;  // which call was the longest (1 = the first)
  std::uint64_t long_calls = 0;       // calls longer than the period (each an overrun in real time)
};

class PeriodicThread {
 public:
  using Clock = std::chrono::steady_clock;
  // `body(now_s)`: now_s = seconds since `epoch` at the start of the call.
  PeriodicThread(double period_s, Clock::time_point epoch, std::function<void(double now_s)> body);
  ~PeriodicThread();  // stops
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;

  void Start();
  void Stop();  // idempotent; joins
  bool Running() const { return running_.load(); }
  PeriodicStats Stats() const;
  // Counts a call made elsewhere (e.g. simulated time on the caller's thread).
  void Account(double call_s, bool overrun);

 private:
  void Main();
  double period_s_;
  Clock::time_point epoch_;
  std::function<void(double)> body_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::mutex wake_mu_;  // taken only between calls, to sleep until the deadline
  std::condition_variable wake_cv_;
  std::atomic<std::uint64_t> calls_{0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<double> max_call_s_{0};
  std::atomic<std::uint64_t> max_call_number_{0};
  std::atomic<double> total_call_s_{0};
  std::atomic<std::uint64_t> long_calls_{0};
  // Call durations, log-spaced bins (PeriodicStats::p50_call_s): fixed size, nothing allocated.
  static constexpr int kBinsPerDecade = 20, kBins = 8 * kBinsPerDecade;  // 1e-7 … 10 s
  std::array<std::atomic<std::uint64_t>, kBins> histogram_{};
};

}  // namespace trueaxis::runtime
