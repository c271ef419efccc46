#pragma once
// TemperatureSource: a set of named temperature channels (MISSION M2): the
// virtual machine's sensors in process, or RTD/ADC modules over MODBUS TCP.
// Raw readings only: filtering, calibration and fault detection live in
// signal/, so they behave the same for every source.
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "trueaxis/hw/lifecycle.hpp"

namespace trueaxis::hw {

// What a channel's measuring chain can report at all: a transmitter's span, a module's input
// range, a digital sensor's datasheet range. A reading at either end is the chain's rail, not a
// temperature (a 0–50 °C transmitter reads 50.0 however hot the nut is). Unknown: ±infinity.
struct MeasuringRange {
  double min_c = -std::numeric_limits<double>::infinity();
  double max_c = std::numeric_limits<double>::infinity();
  bool known() const { return std::isfinite(min_c) && std::isfinite(max_c); }
};

struct RawTemperature {
  double temp_c = 0;           // converted to °C with the hardware's own scaling
  bool hardware_fault = false; // the device itself flags the channel (open wire, burn-out, over range)
};

class TemperatureSource : public HardwareLifecycle {
 public:
  virtual ~TemperatureSource() = default;
  virtual std::size_t ChannelCount() const = 0;
  virtual std::string ChannelName(std::size_t channel) const = 0;  // "ambient", "x_nut", ...
  // Fills out[0..ChannelCount()). False when the source cannot be read at all
  // (link fault); then `out` is left unchanged.
  virtual bool Read(std::span<RawTemperature> out) = 0;
  // The channel's measuring range (sensor kind, module range code); does not allocate.
  virtual MeasuringRange ChannelMeasuringRange(std::size_t /*channel*/) const { return {}; }
};

}  // namespace trueaxis::hw
