#include "trueaxis/runtime/loop_runner.hpp"

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
  return true;
}

std::string LoopStats::BriefReport() const {
  return fmt::format("{} cycles, {} overruns, cycle time mean {:.1f} µs max {:.1f} µs", cycles, overruns,
                     mean_cycle_s * 1e6, max_cycle_s * 1e6);
}

LoopRunner::LoopRunner(Compensator& compensator, hw::CncLink& link, hw::TemperatureSource& source, LoopOptions options,
                       CycleObserver* observer)
    : compensator_(compensator), link_(link), source_(source), options_(options), observer_(observer) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("loop options: " + why);
}

LoopRunner::~LoopRunner() { Stop(); }

void LoopRunner::Start() {
  if (running_.exchange(true)) return;
  stop_.store(false);
  thread_ = std::thread([this] { ThreadMain(); });
}

void LoopRunner::Stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mu_);
    stop_.store(true);
  }
  wake_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  running_.store(false);
}

void LoopRunner::Account(double cycle_s, bool overrun) {
  cycles_.fetch_add(1, std::memory_order_relaxed);
  if (overrun) overruns_.fetch_add(1, std::memory_order_relaxed);
  // single writer: plain load/store is enough
  if (cycle_s > max_cycle_s_.load(std::memory_order_relaxed)) max_cycle_s_.store(cycle_s, std::memory_order_relaxed);
  total_cycle_s_.store(total_cycle_s_.load(std::memory_order_relaxed) + cycle_s, std::memory_order_relaxed);
}

void LoopRunner::ThreadMain() {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.period_s));
  const auto t0 = Clock::now();
  auto deadline = t0;
  while (!stop_.load(std::memory_order_relaxed)) {
    if (plant_advance_) plant_advance_(options_.period_s);
    const auto start = Clock::now();
    const double now_s = std::chrono::duration<double>(start - t0).count();
    const CycleStatus& status = compensator_.RunCycle(link_, source_, now_s);
    if (observer_) observer_->OnCycle(status);
    const auto end = Clock::now();
    deadline += period;
    const bool overrun = end > deadline;
    if (overrun) {
      // skip the missed deadlines: the next cycle starts on the period grid after now
      const auto missed = (end - deadline) / period + 1;
      deadline += missed * period;
    }
    Account(std::chrono::duration<double>(end - start).count(), overrun);
    std::unique_lock<std::mutex> lock(wake_mu_);  // outside the cycle: the cycle itself takes no lock
    wake_cv_.wait_until(lock, deadline, [this] { return stop_.load(std::memory_order_relaxed); });
  }
}

void LoopRunner::StepSimulated(std::uint64_t cycles, const std::function<void(double)>& advance) {
  using Clock = std::chrono::steady_clock;
  for (std::uint64_t c = 0; c < cycles; ++c) {
    if (advance) advance(options_.period_s);
    ++sim_cycles_;
    const auto start = Clock::now();
    const CycleStatus& status = compensator_.RunCycle(link_, source_, SimulatedTimeS());
    if (observer_) observer_->OnCycle(status);
    Account(std::chrono::duration<double>(Clock::now() - start).count(), false);
  }
}

LoopStats LoopRunner::Stats() const {
  LoopStats s;
  s.cycles = cycles_.load();
  s.overruns = overruns_.load();
  s.max_cycle_s = max_cycle_s_.load();
  s.mean_cycle_s = s.cycles ? total_cycle_s_.load() / static_cast<double>(s.cycles) : 0;
  return s;
}

}  // namespace trueaxis::runtime
