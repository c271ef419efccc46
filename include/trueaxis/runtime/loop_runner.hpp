#pragma once
// LoopRunner: runs the compensator's cycle, with its I/O phases, either
//  * in real time: the step on its own thread every `period_s`
//    (PeriodicThread: absolute deadlines, overruns counted, missed deadlines
//    skipped). For real hardware the I/O runs on two I/O workers with their own
//    rates — the CNC worker every `period_s` (write the latest command, read
//    the window), the temperature worker every `temperature_period_s` — each
//    handing the step its latest snapshot through a wait-free LatestValue. The
//    step never waits on a socket: a stalled or flapping terminal only makes the
//    snapshots old, which the step treats as a fault through the limiter
//    (docs/runtime.md, *Timing contract*). For an in-process plant
//    (SetPlantAdvance: the virtual machine, moved on by the loop) the I/O
//    phases run inline on the loop thread: they never block, and the plant is
//    touched by one thread only;
//  * in simulated time on the caller's thread (StepSimulated): before each
//    cycle the plant advances by one period, the I/O phases run inline
//    (temperatures at their own rate in simulated time), so a working day at
//    10 ms runs in seconds.
//
// An optional CycleObserver sees every CycleStatus on the loop's thread; it
// must be as real-time safe as the cycle itself in real-time mode (e.g. push
// into a preallocated ring, see CycleRecorder).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/io_snapshot.hpp"
#include "trueaxis/runtime/latest_value.hpp"
#include "trueaxis/core/periodic_thread.hpp"

namespace trueaxis::runtime {

struct LoopOptions {
  double period_s = 0.010;
  // Temperatures change over seconds: they are read at this interval (10 Hz by default; never
  // more often than once per cycle).
  double temperature_period_s = 0.1;
  bool IsValid(std::string* why) const;
};

struct LoopStats {
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;
  double max_cycle_s = 0;   // longest cycle (step + observer, + inline I/O for an in-process plant)
  double mean_cycle_s = 0;
  double p50_cycle_s = 0, p99_cycle_s = 0;  // PeriodicStats::p50_call_s
  std::uint64_t max_cycle_number = 0;       // which cycle was the longest (1 = the first)
  // Cycles that took longer than the period. In real time each is an overrun; in simulated time
  // (StepSimulated) there is no deadline, so no overrun is counted, but these would have been.
  std::uint64_t long_cycles = 0;
  bool io_workers = false;  // the I/O ran on its own workers
  core::PeriodicStats cnc_io;     // the CNC worker's calls (write + read), when io_workers
  core::PeriodicStats temperature_io;
  std::string BriefReport() const;
};

class CycleObserver {
 public:
  virtual ~CycleObserver() = default;
  virtual void OnCycle(const CycleStatus& status) = 0;
};

class LoopRunner {
 public:
  // Throws std::invalid_argument on invalid options.
  LoopRunner(Compensator& compensator, hw::CncLink& link, signal::JudgedTemperatureSource& source, LoopOptions options,
             CycleObserver* observer = nullptr);
  ~LoopRunner();  // stops the threads
  LoopRunner(const LoopRunner&) = delete;
  LoopRunner& operator=(const LoopRunner&) = delete;

  // Real-time mode with an in-process plant: `advance(dt_s)` is called on the loop thread before
  // each cycle (e.g. to move the virtual machine on in step with the loop); the I/O phases then
  // run inline on the loop thread. Call before Start.
  void SetPlantAdvance(std::function<void(double dt_s)> advance) { plant_advance_ = std::move(advance); }
  // Throws std::invalid_argument when the period is too long for the staleness limit
  // (period_s > link_stale_after_s / 2 with I/O workers).
  void Start();
  void Stop();  // idempotent; joins (an I/O worker blocked on a socket returns at its timeout)
  bool Running() const { return loop_.Running(); }

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
  double Now() const;
  void InlineCycle(double now_s);     // I/O phases inline around the step
  void SteppingCycle(double now_s);   // the step on the workers' latest snapshots
  void CncWorkerCall();               // write the latest command, read the window, publish
  void TemperatureWorkerCall();       // read the temperatures, publish

  Compensator& compensator_;
  hw::CncLink& link_;
  signal::JudgedTemperatureSource& source_;
  LoopOptions options_;
  CycleObserver* observer_;
  std::function<void(double)> plant_advance_;
  core::PeriodicThread::Clock::time_point epoch_;

  // Inline I/O (simulated time, in-process plant).
  TemperatureSnapshot temperatures_;
  CncSnapshot cnc_;
  std::uint64_t temperature_reads_ = 0;
  std::uint64_t cnc_reads_ = 0;
  double last_temperature_read_s_ = 0;

  // I/O workers.
  LatestValue<TemperatureSnapshot> temperature_slot_;
  LatestValue<CncSnapshot> cnc_slot_;
  LatestValue<CncCommand> command_slot_;
  // CNC worker: the last command tried, its result, the last command the CNC accepted.
  std::uint64_t attempted_sequence_ = 0;
  bool write_failed_ = false;
  std::uint64_t written_sequence_ = 0;
  std::uint64_t worker_temperature_reads_ = 0;
  std::uint64_t worker_cnc_reads_ = 0;
  std::atomic<bool> io_workers_{false};

  core::PeriodicThread loop_;
  core::PeriodicThread cnc_worker_;
  core::PeriodicThread temperature_worker_;
  std::uint64_t sim_cycles_ = 0;
  double sim_pause_s_ = 0;
};

}  // namespace trueaxis::runtime
