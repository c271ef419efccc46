#pragma once
// HalTemperatureSource: temperature channels read from HAL pins (C.temp.NAME float in, °C, and
// C.temp.NAME-fault bit in: the device flags the channel), for a machine whose sensors already
// reach HAL (an EtherCAT/Mesa analog input, or the virtual machine of `trueaxis-hal --plant`).
// The alternative is the RTD modules over MODBUS TCP, as in `trueaxis run` (docs/linuxcnc.md).
#include <string>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"

namespace trueaxis::linuxcnc {

class HalTemperatureSource : public hw::TemperatureSource {
 public:
  HalTemperatureSource(HalComponent& component, std::vector<std::string> channel_names);
  std::size_t ChannelCount() const override { return names_.size(); }
  std::string ChannelName(std::size_t channel) const override { return names_[channel]; }
  bool Read(std::span<hw::RawTemperature> out) override;
  // The temperature pins not netted yet, by pin name ("trueaxis.temp.x_nut").
  std::vector<std::string> PinsNotNetted() const;

 private:
  std::string prefix_;  // "<component>.temp."
  std::vector<std::string> names_;
  std::vector<Pin<double>> value_;
  std::vector<Pin<bool>> fault_;
};

}  // namespace trueaxis::linuxcnc
