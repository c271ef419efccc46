#pragma once
// The one mock hardware of the tests and benches: a CNC link and a temperature source.
//
// Two ways to drive it:
// - single-threaded tests (the runtime's) set the plain public fields between calls;
// - tests whose other thread reads it (a MODBUS terminal's machine thread, an I/O worker) use the
//   locked setters and getters (SetAxis, SetReadOk, Compensation(), ...). Read() and
//   WriteCompensation() always take the mock's own mutex.
// Read/Write allocate nothing (the no-allocation tests run through them) unless
// `record_history` is switched on.
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/judged_temperature.hpp"

namespace trueaxis::testing {

// kUnlocked: a single-threaded benchmark, whose figures must be the compensator's, not the mutex's.
enum class MockLocking { kLocked, kUnlocked };

class MockCnc : public hw::CncLink {
  template <class F>
  auto Locked(F f) const -> decltype(f()) {
    std::lock_guard<std::mutex> lock(mu_);
    return f();
  }

 public:
  explicit MockCnc(std::vector<std::string> names, MockLocking locking = MockLocking::kLocked)
      : names_(std::move(names)), axes(names_.size()), cnc_value_um(names_.size(), 0.0), attempted_um(names_.size(), 0.0),
        locked_(locking == MockLocking::kLocked) {
    machine.compensation_enabled = true;
  }
  std::size_t AxisCount() const override { return names_.size(); }
  std::string AxisName(std::size_t i) const override { return names_.at(i); }
  bool Read(std::span<hw::AxisState> out, hw::CncState& m) override {
    std::unique_lock<std::mutex> lock(mu_, std::defer_lock);
    if (locked_) {
      lock.lock();
      hang_cv_.wait_for(lock, std::chrono::seconds(10), [&] { return !hang_; });
    }
    ++reads;
    if (fail_read) return false;
    for (std::size_t i = 0; i < axes.size(); ++i) {
      out[i] = axes[i];
      if (report_applied) out[i].applied_um = cnc_value_um[i];
    }
    m = machine;
    return true;
  }
  bool WriteCompensation(std::span<const double> c) override {
    std::unique_lock<std::mutex> lock(mu_, std::defer_lock);
    if (locked_) lock.lock();
    ++write_attempts;
    for (std::size_t i = 0; i < c.size(); ++i) attempted_um[i] = c[i];
    if (fail_write) return false;
    ++writes;
    for (std::size_t i = 0; i < c.size(); ++i) cnc_value_um[i] = c[i];
    if (record_history) history_.emplace_back(c.begin(), c.end());
    return true;
  }

  // Locked access, for tests that share the mock with another thread.
  void SetAxis(std::size_t a, hw::AxisState s) { Locked([&] { axes.at(a) = s; }); }
  void SetState(hw::CncState s) { Locked([&] { machine = s; }); }
  void SetReadOk(bool ok) { Locked([&] { fail_read = !ok; }); }
  void SetWriteOk(bool ok) { Locked([&] { fail_write = !ok; }); }
  // While hung, Read() blocks (up to 10 s): a CNC that stops answering its terminal.
  void SetHang(bool hang) {
    Locked([&] { hang_ = hang; });
    hang_cv_.notify_all();
  }
  std::vector<double> Compensation() const { return Locked([&] { return cnc_value_um; }); }
  long Writes() const { return Locked([&] { return writes; }); }
  long WriteAttempts() const { return Locked([&] { return write_attempts; }); }
  long Reads() const { return Locked([&] { return reads; }); }
  std::vector<std::vector<double>> History() const { return Locked([&] { return history_; }); }

  std::vector<std::string> names_;
  std::vector<hw::AxisState> axes;
  hw::CncState machine;
  bool fail_read = false;
  bool fail_write = false;
  bool record_history = false;       // keep every accepted vector (History()); allocates
  std::vector<double> cnc_value_um;  // what the CNC holds (successful writes only)
  bool report_applied = true;        // Read() reports cnc_value_um as the applied compensation
  std::vector<double> attempted_um;  // last value offered, even if the write failed
  long reads = 0, writes = 0, write_attempts = 0;

 private:
  mutable std::mutex mu_;
  std::condition_variable hang_cv_;
  bool locked_ = true;
  bool hang_ = false;
  std::vector<std::vector<double>> history_;
};

// A raw temperature source (for the pipeline's tests: wrap it in signal::MonitoredTemperatureSource)
// and, for the runtime's tests, a judged one whose verdicts the test sets: a channel flagged
// faulty (SetFault, Set(..., true)) or not finite is judged hardware_fault, every other one ok
// with its value as it is. The judge's own rules are tested in tests/signal; the runtime's tests
// test what the step does with a verdict.
class MockTemperatures : public hw::TemperatureSource, public signal::JudgedTemperatureSource {
 public:
  MockTemperatures(std::vector<std::string> names, double initial_c, MockLocking locking = MockLocking::kLocked)
      : names_(std::move(names)), values(names_.size()), locked_(locking == MockLocking::kLocked) {
    for (auto& v : values) v.temp_c = initial_c;
  }
  // n channels named t0, t1, ... at 20.0, 20.5, 21.0, ... °C (distinct values, so a mix-up shows).
  explicit MockTemperatures(std::size_t n) : values(n) {
    for (std::size_t i = 0; i < n; ++i) {
      names_.push_back("t" + std::to_string(i));
      values[i].temp_c = 20.0 + 0.5 * static_cast<double>(i);
    }
  }
  std::size_t ChannelCount() const override { return names_.size(); }
  std::string ChannelName(std::size_t i) const override { return names_.at(i); }
  bool Read(std::span<hw::RawTemperature> out) override {
    std::unique_lock<std::mutex> lock(mu_, std::defer_lock);
    if (locked_) lock.lock();
    if (fail) return false;
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
    return true;
  }
  bool Read(std::span<signal::JudgedTemperature> out) override {
    std::unique_lock<std::mutex> lock(mu_, std::defer_lock);
    if (locked_) lock.lock();
    if (fail) return false;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const hw::RawTemperature& v = values[i];
      const bool ok = !v.hardware_fault && std::isfinite(v.temp_c);
      out[i] = {ok ? v.temp_c : signal::JudgedTemperature::kNaN, v.temp_c,
                ok ? signal::ChannelStatus::kOk : signal::ChannelStatus::kHardwareFault};
    }
    return true;
  }
  void Set(const std::string& name, double c) {
    std::lock_guard<std::mutex> lock(mu_);
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) values[i].temp_c = c;
  }
  void SetFault(const std::string& name, bool f) {
    std::lock_guard<std::mutex> lock(mu_);
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) values[i].hardware_fault = f;
  }
  void Set(std::size_t channel, double c, bool fault = false) {
    std::lock_guard<std::mutex> lock(mu_);
    values.at(channel) = {c, fault};
  }
  void SetOk(bool ok) {
    std::lock_guard<std::mutex> lock(mu_);
    fail = !ok;
  }
  hw::MeasuringRange ChannelMeasuringRange(std::size_t channel) const override {
    return channel < ranges.size() ? ranges[channel] : hw::MeasuringRange{};
  }

  std::vector<std::string> names_;
  std::vector<hw::RawTemperature> values;
  std::vector<hw::MeasuringRange> ranges;  // per channel; missing = unknown
  bool fail = false;

 private:
  std::mutex mu_;
  bool locked_ = true;
};

}  // namespace trueaxis::testing
