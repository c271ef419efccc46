#include "trueaxis/runtime/loop_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::runtime {

bool LoopOptions::IsValid(std::string* why) const {
  if (!(period_s >= 1e-4 && period_s <= 10)) {
    if (why) *why = fmt::format("period_s must be in [0.0001, 10] s, got {}", period_s);
    return false;
  }
  if (!(temperature_period_s > 0 && temperature_period_s <= 60)) {
    if (why) *why = fmt::format("temperature_period_s must be in (0, 60] s, got {}", temperature_period_s);
    return false;
  }
  return true;
}

std::string LoopStats::BriefReport() const {
  std::string s = fmt::format("{} cycles, {} overruns, cycle time p50 {:.1f} µs p99 {:.1f} µs max {:.1f} µs (cycle {})",
                              cycles, overruns, p50_cycle_s * 1e6, p99_cycle_s * 1e6, max_cycle_s * 1e6, max_cycle_number);
  if (io_workers)
    s += fmt::format("; CNC I/O {} calls max {:.1f} ms, temperature I/O {} calls max {:.1f} ms", cnc_io.calls,
                     cnc_io.max_call_s * 1e3, temperature_io.calls, temperature_io.max_call_s * 1e3);
  return s;
}

LoopRunner::LoopRunner(Compensator& compensator, hw::CncLink& link, signal::JudgedTemperatureSource& source, LoopOptions options,
                       CycleObserver* observer)
    : compensator_(compensator),
      link_(link),
      source_(source),
      options_(options),
      observer_(observer),
      epoch_(core::PeriodicThread::Clock::now()),
      temperatures_(compensator.MakeTemperatureSnapshot()),
      cnc_(compensator.MakeCncSnapshot()),
      temperature_slot_(compensator.MakeTemperatureSnapshot()),
      cnc_slot_(compensator.MakeCncSnapshot()),
      command_slot_(CncCommand(compensator.axes().size())),
      loop_(options.period_s, epoch_,
            [this](double now_s) {
              if (io_workers_.load(std::memory_order_relaxed)) {
                SteppingCycle(now_s);
              } else {
                if (plant_advance_) plant_advance_(options_.period_s);
                InlineCycle(now_s);
              }
            }),
      cnc_worker_(options.period_s, epoch_, [this](double) { CncWorkerCall(); }),
      temperature_worker_(std::max(options.temperature_period_s, options.period_s), epoch_, [this](double) { TemperatureWorkerCall(); }) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("loop options: " + why);
}

LoopRunner::~LoopRunner() { Stop(); }

double LoopRunner::Now() const {
  return std::chrono::duration<double>(core::PeriodicThread::Clock::now() - epoch_).count();
}

void LoopRunner::Start() {
  if (loop_.Running()) return;
  const bool workers = !plant_advance_;
  if (workers && options_.period_s > compensator_.options().link_stale_after_s / 2)
    throw std::invalid_argument(fmt::format(
        "loop period {} s is too long for link_stale_after_s = {} s: every CNC snapshot would be stale "
        "(raise [link] stale_after_s to at least twice the period)",
        options_.period_s, compensator_.options().link_stale_after_s));
  io_workers_.store(workers);
  if (workers) {
    temperature_worker_.Start();
    cnc_worker_.Start();
  }
  loop_.Start();
}

void LoopRunner::Stop() {
  loop_.Stop();
  cnc_worker_.Stop();
  temperature_worker_.Stop();
}

void LoopRunner::InlineCycle(double now_s) {
  const double tolerance = 1e-6 * options_.period_s;
  if (temperature_reads_ == 0 || now_s - last_temperature_read_s_ >= options_.temperature_period_s - tolerance) {
    ReadTemperatures(source_, now_s, ++temperature_reads_, temperatures_);
    last_temperature_read_s_ = now_s;
  }
  ReadCnc(link_, now_s, ++cnc_reads_, cnc_);
  compensator_.Cycle(temperatures_, cnc_, now_s);
  const CycleStatus& status = compensator_.CommitWrite(WriteCnc(link_, compensator_.command()));
  if (observer_) observer_->OnCycle(status);
}

void LoopRunner::SteppingCycle(double now_s) {
  temperature_slot_.Fetch();
  cnc_slot_.Fetch();
  compensator_.Cycle(temperature_slot_.Front(), cnc_slot_.Front(), now_s);
  if (compensator_.PickUpPending()) {
    // Nothing goes to the CNC before its applied compensation is known: the first value written is
    // one step from what the CNC holds (pick-up without a jump), never the shaper's zero.
    const CycleStatus& status = compensator_.CommitWrite(false);
    if (observer_) observer_->OnCycle(status);
    return;
  }
  const CncCommand& command = compensator_.command();
  CncCommand& out = command_slot_.Back();
  out.sequence = command.sequence;
  std::copy(command.correction_um.begin(), command.correction_um.end(), out.correction_um.begin());
  command_slot_.Publish();
  // The write happens on the CNC worker; the step advances its ramp once a later snapshot says the
  // CNC accepted this command (never ahead of what the CNC holds).
  const CycleStatus& status = compensator_.AwaitWrite();
  if (observer_) observer_->OnCycle(status);
}

void LoopRunner::CncWorkerCall() {
  // Each command once (the step hands out a new one every cycle once this one is answered).
  command_slot_.Fetch();
  const CncCommand& command = command_slot_.Front();
  if (command.sequence != 0 && command.sequence != attempted_sequence_) {
    attempted_sequence_ = command.sequence;
    write_failed_ = !WriteCnc(link_, command);
    if (!write_failed_) written_sequence_ = command.sequence;
  }
  CncSnapshot& s = cnc_slot_.Back();
  ReadCnc(link_, 0, ++worker_cnc_reads_, s);
  s.sampled_at_s = Now();  // when the answer came (a read may block up to the link's timeout)
  s.attempted_sequence = attempted_sequence_;
  s.write_failed = write_failed_;
  s.written_sequence = written_sequence_;
  cnc_slot_.Publish();
}

void LoopRunner::TemperatureWorkerCall() {
  TemperatureSnapshot& s = temperature_slot_.Back();
  ReadTemperatures(source_, 0, ++worker_temperature_reads_, s);
  s.sampled_at_s = Now();
  temperature_slot_.Publish();
}

void LoopRunner::StepSimulated(std::uint64_t cycles, const std::function<void(double)>& advance) {
  using Clock = core::PeriodicThread::Clock;
  for (std::uint64_t c = 0; c < cycles; ++c) {
    if (advance) advance(options_.period_s);
    ++sim_cycles_;
    const auto start = Clock::now();
    InlineCycle(SimulatedTimeS());
    loop_.Account(std::chrono::duration<double>(Clock::now() - start).count(), false);
  }
}

LoopStats LoopRunner::Stats() const {
  const core::PeriodicStats p = loop_.Stats();
  LoopStats s;
  s.cycles = p.calls;
  s.overruns = p.overruns;
  s.max_cycle_s = p.max_call_s;
  s.mean_cycle_s = p.mean_call_s;
  s.p50_cycle_s = p.p50_call_s;
  s.p99_cycle_s = p.p99_call_s;
  s.max_cycle_number = p.max_call_number;
  s.long_cycles = p.long_calls;
  s.io_workers = io_workers_.load();
  s.cnc_io = cnc_worker_.Stats();
  s.temperature_io = temperature_worker_.Stats();
  return s;
}

}  // namespace trueaxis::runtime
