#pragma once
// PeriodicThread: the one periodic loop of the program. Calls a function at once and then every
// `period_s` on its own thread, on absolute deadlines of the steady clock (no drift: a slow call
// does not push the later ones back). A call finishing after the next deadline is an overrun,
// counted; the missed deadlines are skipped (the next call starts on the period grid after now),
// never caught up in a burst. Stop() wakes the thread at once (a 10 s period never delays SIGINT)
// and joins it. Wake() asks for one call out of turn, now (a MODBUS client wrote new compensation
// registers); the grid stays where it was.
//
// Every loop that runs at a period uses it: the real-time loop and each I/O worker (LoopRunner,
// all timed from one epoch, so their timestamps are comparable), the terminal's machine exchange
// (drivers::ModbusMachineServer) and its slow temperature poller (terminal::PolledTemperatureSource),
// and the low-rate publishers (the web front end's shop sampler and synthetic shop, the MQTT relay,
// the MTConnect agent). The thread itself allocates nothing once started.
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

namespace trueaxis::core {

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
  PeriodicThread() = default;  // Start(period_s, body) gives it its work
  // `body(now_s)`: now_s = seconds since `epoch` at the start of the call.
  PeriodicThread(double period_s, Clock::time_point epoch, std::function<void(double now_s)> body);
  ~PeriodicThread();  // stops
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;

  void Start();  // no-op while running
  // Stops a running thread, then starts it with this period (> 0) and body, timed from now.
  void Start(double period_s, std::function<void(double now_s)> body);
  void Stop();  // idempotent; joins; the body is not called again
  void Wake();  // one call as soon as the running one (if any) ends; several Wake()s before it: one call
  bool Running() const { return running_.load(); }
  PeriodicStats Stats() const;
  // Counts a call made elsewhere (e.g. simulated time on the caller's thread).
  void Account(double call_s, bool overrun);

 private:
  void Main();
  double period_s_ = 1;
  Clock::time_point epoch_{};
  std::function<void(double)> body_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex wake_mu_;  // taken only between calls, to sleep until the deadline
  std::condition_variable wake_cv_;
  bool stop_ = false;   // guarded by wake_mu_
  bool woken_ = false;  // guarded by wake_mu_
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

}  // namespace trueaxis::core
