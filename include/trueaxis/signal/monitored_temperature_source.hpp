#pragma once
// MonitoredTemperatureSource: the one temperature pipeline. It wraps a raw
// hw::TemperatureSource and passes every reading through a TemperatureMonitor
// (calibration, spike rejection, median, low-pass, fault rules), and delivers
// the monitor's verdict per channel (JudgedTemperature): the filtered value
// while the channel is ok, its status otherwise. It is a JudgedTemperatureSource,
// not a raw source: the compensation loop reads it, and it cannot be wrapped again
// or judged a second time.
//
//   MonitoredTemperatureSource judged(raw_source, options);
//   judged.monitor().SetCalibration(ReadCalibrationFile("cal.json"));
//   the runtime reads `judged`; `judged.monitor()` has the statuses and details.
#include <functional>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/judged_temperature.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::signal {

class MonitoredTemperatureSource final : public JudgedTemperatureSource {
 public:
  // `clock_s` returns the current time in seconds (default: steady clock).
  // It is called once per Read(); it must not allocate.
  MonitoredTemperatureSource(hw::TemperatureSource& inner, MonitorOptions options = {},
                             std::function<double()> clock_s = {});

  std::size_t ChannelCount() const override { return monitor_.ChannelCount(); }
  std::string ChannelName(std::size_t channel) const override { return monitor_.ChannelName(channel); }
  // Reads the inner source, updates the monitor and writes its verdicts. False (and `out`
  // untouched) when the inner source fails; the monitor then counts the outage and turns
  // channels to no_data after FaultOptions::stale_after_s.
  bool Read(std::span<JudgedTemperature> out) override;

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
