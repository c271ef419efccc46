#pragma once
// LoopRunner: runs Compensator::RunCycle against a CNC link and a
// temperature source, either
//  * in real time on its own thread, one cycle per `period_s` (absolute
//    deadlines on the steady clock; a cycle finishing after the next
//    deadline is an overrun, counted, and missed deadlines are skipped, never
//    caught up in a burst), or
//  * in simulated time on the caller's thread (StepSimulated): before each
//    cycle the plant (e.g. the virtual machine) advances by one period, so a
//    working day at 10 ms runs in seconds.
//
// An optional CycleObserver sees every CycleStatus on the loop's thread; it
// must be as real-time safe as the cycle itself in real-time mode (e.g. push
// into a preallocated ring, see CycleRecorder).
#include <atomic>
#include <mutex>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {

struct LoopOptions {
  double period_s = 0.010;
  bool IsValid(std::string* why) const;
};

struct LoopStats {
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;
  double max_cycle_s = 0;   // longest RunCycle (+observer) duration
  double mean_cycle_s = 0;
  std::string BriefReport() const;
};

class CycleObserver {
 public:
  virtual ~CycleObserver() = default;
  virtual void OnCycle(const CycleStatus& status) = 0;
};

class LoopRunner {
 public:
  LoopRunner(Compensator& compensator, hw::CncLink& link, hw::TemperatureSource& source, LoopOptions options,
             CycleObserver* observer = nullptr);
  ~LoopRunner();  // stops the thread
  LoopRunner(const LoopRunner&) = delete;
  LoopRunner& operator=(const LoopRunner&) = delete;

  // Real-time mode. `SetPlantAdvance` (before Start) installs a hook called
  // on the loop thread before each cycle with the period, e.g. to move an
  // in-process virtual machine on in step with the loop (no lock needed: only
  // the loop thread touches it).
  void SetPlantAdvance(std::function<void(double dt_s)> advance) { plant_advance_ = std::move(advance); }
  void Start();
  void Stop();  // idempotent; joins
  bool Running() const { return running_.load(); }

  // Simulated-time mode (do not mix with Start on the same runner while running).
  // Runs `cycles` cycles; before each, `advance(period_s)` moves the plant on.
  // Simulated time starts at 0 and continues across calls.
  void StepSimulated(std::uint64_t cycles, const std::function<void(double dt_s)>& advance);
  double SimulatedTimeS() const { return static_cast<double>(sim_cycles_) * options_.period_s + sim_pause_s_; }
  // The loop was not running for `seconds` of simulated time (e.g. the
  // machine stood switched off overnight): the clock jumps, so time-based
  // checks (rate of change, hold times) see the real elapsed time.
  void PauseSimulated(double seconds) { sim_pause_s_ += seconds; }

  LoopStats Stats() const;

 private:
  void ThreadMain();
  void Account(double cycle_s, bool overrun);

  Compensator& compensator_;
  hw::CncLink& link_;
  hw::TemperatureSource& source_;
  LoopOptions options_;
  CycleObserver* observer_;
  std::function<void(double)> plant_advance_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  // The loop waits for its next deadline here, so Stop() wakes it at once
  // instead of after up to a whole period (10 s periods made SIGINT wait).
  std::mutex wake_mu_;
  std::condition_variable wake_cv_;
  std::uint64_t sim_cycles_ = 0;
  double sim_pause_s_ = 0;
  std::atomic<std::uint64_t> cycles_{0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<double> max_cycle_s_{0};
  std::atomic<double> total_cycle_s_{0};
};

}  // namespace trueaxis::runtime
