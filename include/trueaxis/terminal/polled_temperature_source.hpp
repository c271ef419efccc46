#pragma once
// PolledTemperatureSource: reads a slow temperature source (1-Wire: ~750 ms
// per sensor; RTD modules over the network) on its own thread every
// period_s, so the terminal's machine thread, which calls Read() every few
// milliseconds, never waits for it. Read() copies the latest values.
//
// The poller is a core::PeriodicThread: a read longer than the period is an overrun, the next
// starts on the period grid (no burst to catch up); Deactivate() does not wait out a period.
//
// Read() returns false when the inner source's last read failed, or when no
// read has completed for stale_after_s (a reader stuck in the kernel or the
// network): a stale number is never served as a live one.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::terminal {

class PolledTemperatureSource final : public hw::TemperatureSource {
 public:
  PolledTemperatureSource(std::unique_ptr<hw::TemperatureSource> inner, double period_s, double stale_after_s);
  ~PolledTemperatureSource() override;  // Deactivate()

  std::size_t ChannelCount() const override { return inner_->ChannelCount(); }
  std::string ChannelName(std::size_t channel) const override { return inner_->ChannelName(channel); }
  bool Read(std::span<hw::RawTemperature> out) override;
  hw::MeasuringRange ChannelMeasuringRange(std::size_t channel) const override { return inner_->ChannelMeasuringRange(channel); }

  bool Configure(std::string* error) override;
  // Activates the inner source (a failure is reported but the thread starts
  // anyway: the inner source retries on its own) and starts the thread.
  bool Activate(std::string* error) override;
  void Deactivate() override;  // stops the thread, then the inner source

  // The inner source, for status (read it only while deactivated or accept a racy view).
  hw::TemperatureSource& inner() { return *inner_; }
  std::uint64_t polls() const { return polls_.load(); }

 private:
  void Poll();  // one read of the inner source (the poller thread)
  std::unique_ptr<hw::TemperatureSource> inner_;
  std::chrono::duration<double> period_, stale_after_;
  std::mutex mu_;
  std::vector<hw::RawTemperature> latest_;
  bool latest_ok_ = false;
  std::chrono::steady_clock::time_point latest_time_{};
  std::atomic<std::uint64_t> polls_{0};
  std::vector<hw::RawTemperature> buffer_;  // the poller's own
  core::PeriodicThread poller_;  // last: stopped first
};

}  // namespace trueaxis::terminal
