#pragma once
// MonitoredTemperatureSource: a TemperatureSource that wraps another one and
// passes every reading through a TemperatureMonitor (calibration, spike
// rejection, median, low-pass, fault rules). Code written against
// hw::TemperatureSource (the runtime compensator) gets filtered, calibrated
// values without change: a channel whose status is not ok is delivered with
// hardware_fault = true and its last good value, so the consumer's own
// fallback policy takes over.
//
//   MonitoredTemperatureSource filtered(raw_source, options);
//   filtered.monitor().SetCalibration(ReadCalibrationFile("cal.json"));
//   runtime uses `filtered` as its TemperatureSource; `filtered.monitor()` has the statuses.
#include <functional>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::signal {

class MonitoredTemperatureSource : public hw::TemperatureSource {
 public:
  // `clock_s` returns the current time in seconds (default: steady clock).
  // It is called once per Read(); it must not allocate.
  MonitoredTemperatureSource(hw::TemperatureSource& inner, MonitorOptions options = {},
                             std::function<double()> clock_s = {});

  std::size_t ChannelCount() const override { return monitor_.ChannelCount(); }
  std::string ChannelName(std::size_t channel) const override { return monitor_.ChannelName(channel); }
  // Reads the inner source and updates the monitor. False (and `out`
  // untouched) when the inner source fails; the monitor then counts the
  // outage and turns channels to no_data after FaultOptions::stale_after_s.
  bool Read(std::span<hw::RawTemperature> out) override;

  TemperatureMonitor& monitor() { return monitor_; }
  const TemperatureMonitor& monitor() const { return monitor_; }

 private:
  static std::vector<std::string> Names(const hw::TemperatureSource& s);
  hw::TemperatureSource& inner_;
  TemperatureMonitor monitor_;
  std::function<double()> clock_s_;
  std::vector<hw::RawTemperature> raw_;  // sized once
};

}  // namespace trueaxis::signal
