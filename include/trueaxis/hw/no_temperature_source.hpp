#pragma once
// NoTemperatureSource: a machine run without temperature channels (a MODBUS terminal without RTD
// modules, for a geometric-only model): nothing to read, and the read never fails. A model that
// needs a sensor is refused when it is bound (runtime/bound_model.hpp), never run without it.
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::hw {

class NoTemperatureSource final : public TemperatureSource {
 public:
  std::size_t ChannelCount() const override { return 0; }
  std::string ChannelName(std::size_t /*channel*/) const override { return {}; }
  bool Read(std::span<RawTemperature> /*out*/) override { return true; }
};

}  // namespace trueaxis::hw
