#pragma once
// MonitoredTemperatureSource: puts seed 000's temperature signal processing
// (signal::TemperatureMonitor: calibration against the reference sensor,
// spike rejection, median and low-pass filtering, fault detection with
// hysteresis) in front of the compensator, as a TemperatureSource itself:
// each Read() reads the raw source, updates the monitor and hands out the
// calibrated, filtered value; a channel whose status is not ok is flagged
// `hardware_fault`, so the compensator's own policy (last good value, then
// fallback) takes over. Real-time safe: no allocation, no lock per Read.
#include <functional>
#include <memory>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::runtime {

class MonitoredTemperatureSource : public hw::TemperatureSource {
 public:
  // `clock` returns the time of the current cycle, s (steady clock, or the simulated loop time).
  MonitoredTemperatureSource(hw::TemperatureSource& inner, signal::MonitorOptions options,
                             std::function<double()> clock);
  std::size_t ChannelCount() const override { return inner_.ChannelCount(); }
  std::string ChannelName(std::size_t channel) const override { return inner_.ChannelName(channel); }
  bool Read(std::span<hw::RawTemperature> out) override;

  signal::TemperatureMonitor& monitor() { return monitor_; }
  const signal::TemperatureMonitor& monitor() const { return monitor_; }

 private:
  static std::vector<std::string> Names(const hw::TemperatureSource& s);
  hw::TemperatureSource& inner_;
  signal::TemperatureMonitor monitor_;
  std::function<double()> clock_;
  std::vector<hw::RawTemperature> raw_;
};

}  // namespace trueaxis::runtime
