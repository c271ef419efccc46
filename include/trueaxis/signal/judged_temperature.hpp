#pragma once
// A judged temperature: what the temperature judge (TemperatureMonitor, the one place where the
// per-value rules — calibration, range, rate, stuck, disagreement — are applied) says about one
// channel's latest sample, and the source the compensation loop reads them from.
//
// The runtime takes temperatures only as JudgedTemperature (runtime::TemperatureSnapshot), read
// from a JudgedTemperatureSource: a raw hw::TemperatureSource handed to the loop does not compile,
// so no path feeds the compensator unjudged values (docs/runtime.md, *The temperature judge*).
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "trueaxis/signal/channel_status.hpp"

namespace trueaxis::signal {

struct JudgedTemperature {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double value_c = kNaN;  // the value to use (calibrated, filtered) while usable; NaN otherwise
  double raw_c = kNaN;    // as the source delivered it (for logs and displays)
  ChannelStatus status = ChannelStatus::kNoData;  // the judge's verdict, after its hysteresis
  bool usable() const { return status == ChannelStatus::kOk; }
};

// What the compensation loop reads (runtime::ReadTemperatures): every value judged once.
// Implemented by MonitoredTemperatureSource (a raw source behind the one TemperatureMonitor).
class JudgedTemperatureSource {
 public:
  virtual ~JudgedTemperatureSource() = default;
  virtual std::size_t ChannelCount() const = 0;
  virtual std::string ChannelName(std::size_t channel) const = 0;
  // Fills out[0..ChannelCount()). False when the source could not be read (then `out` is not
  // this read's). Must not allocate.
  virtual bool Read(std::span<JudgedTemperature> out) = 0;
};

}  // namespace trueaxis::signal
