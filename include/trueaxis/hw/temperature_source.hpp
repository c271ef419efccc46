#pragma once
// TemperatureSource: a set of named temperature channels (MISSION M2): the
// virtual machine's sensors in process, or RTD/ADC modules over MODBUS TCP.
// Raw readings only: filtering, calibration and fault detection live in
// signal/, so they behave the same for every source.
#include <cstddef>
#include <span>
#include <string>

#include "trueaxis/hw/lifecycle.hpp"

namespace trueaxis::hw {

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
};

}  // namespace trueaxis::hw
