#include "trueaxis/linuxcnc/hal_temperature_source.hpp"

namespace trueaxis::linuxcnc {

HalTemperatureSource::HalTemperatureSource(HalComponent& component, std::vector<std::string> channel_names)
    : prefix_(component.name() + ".temp."), names_(std::move(channel_names)) {
  for (const auto& n : names_) {
    value_.push_back(component.FloatPin("temp." + n, PinDirection::kIn));
    fault_.push_back(component.BitPin("temp." + n + "-fault", PinDirection::kIn));
  }
}

bool HalTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  for (std::size_t i = 0; i < names_.size() && i < out.size(); ++i) {
    out[i].temp_c = value_[i].Get();
    out[i].hardware_fault = fault_[i].Get();
  }
  return true;
}

std::vector<std::string> HalTemperatureSource::PinsNotNetted() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (!value_[i].Linked()) out.push_back(prefix_ + names_[i]);
  return out;
}

}  // namespace trueaxis::linuxcnc
