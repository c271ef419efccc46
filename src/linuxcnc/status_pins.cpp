#include "trueaxis/linuxcnc/status_pins.hpp"

#include "trueaxis/linuxcnc/hal_cnc_link.hpp"

namespace trueaxis::linuxcnc {

StatusPins::StatusPins(HalComponent& component, const std::vector<std::string>& axis_names) {
  alarm_ = component.BitPin("alarm", PinDirection::kOut);
  alarms_ = component.S32Pin("alarms", PinDirection::kOut);
  active_ = component.BitPin("active", PinDirection::kOut);
  temperatures_ok_ = component.BitPin("temperatures-ok", PinDirection::kOut);
  temperature_age_s_ = component.FloatPin("temperature-age-s", PinDirection::kOut);
  for (const auto& a : axis_names) {
    clamped_.push_back(component.BitPin(HalAxisLetter(a) + ".clamped", PinDirection::kOut));
    thermal_.push_back(component.BitPin(HalAxisLetter(a) + ".thermal", PinDirection::kOut));
    fallback_model_.push_back(component.S32Pin(HalAxisLetter(a) + ".fallback-model", PinDirection::kOut));
  }
}

void StatusPins::OnCycle(const runtime::CycleStatus& s) {
  alarm_.Set(s.alarms != 0);
  alarms_.Set(static_cast<std::int32_t>(s.alarms));
  bool enabled = false;
  for (const auto& a : s.axes) enabled = enabled || a.enabled;
  active_.Set(s.model_id != 0 && enabled);
  temperatures_ok_.Set(s.temperatures_ok);
  temperature_age_s_.Set(s.temperature_age_s);
  for (std::size_t i = 0; i < clamped_.size() && i < s.axes.size(); ++i) {
    clamped_[i].Set(s.axes[i].clamped);
    thermal_[i].Set(s.axes[i].thermal_used);
    fallback_model_[i].Set(static_cast<std::int32_t>(s.axes[i].fallback_model));
  }
}

}  // namespace trueaxis::linuxcnc
