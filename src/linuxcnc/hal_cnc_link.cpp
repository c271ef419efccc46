#include "trueaxis/linuxcnc/hal_cnc_link.hpp"

#include <cctype>
#include <cmath>
#include <limits>

namespace trueaxis::linuxcnc {

std::string HalAxisLetter(const std::string& axis_name) {
  std::string s = axis_name;
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

HalCncLink::HalCncLink(HalComponent& component, std::vector<runtime::AxisInterface> interfaces) {
  for (auto& it : interfaces) {
    const std::string l = HalAxisLetter(it.axis);
    Axis a;
    a.interface = it;
    a.pos_cmd = component.FloatPin(l + ".pos-cmd", PinDirection::kIn);
    a.pos_fb = component.FloatPin(l + ".pos-fb", PinDirection::kIn);
    a.vel_cmd = component.FloatPin(l + ".vel-cmd", PinDirection::kIn);
    a.counts = component.S32Pin(l + ".eoffset-counts", PinDirection::kOut);
    a.scale = component.FloatPin(l + ".eoffset-scale", PinDirection::kOut);
    a.offset_enable = component.BitPin(l + ".eoffset-enable", PinDirection::kOut);
    a.correction_um = component.FloatPin(l + ".correction-um", PinDirection::kOut);
    a.scale.Set(it.pulse_equivalent_um / 1000.0);  // mm per count
    a.offset_enable.Set(true);
    axes_.push_back(std::move(a));
  }
  enable_ = component.BitPin("enable", PinDirection::kIn);
  flood_ = component.BitPin("coolant-flood", PinDirection::kIn);
  mist_ = component.BitPin("coolant-mist", PinDirection::kIn);
}

bool HalCncLink::Read(std::span<hw::AxisState> out, hw::CncState& machine) {
  for (std::size_t i = 0; i < axes_.size() && i < out.size(); ++i) {
    Axis& a = axes_[i];
    const double pos_cmd = a.pos_cmd.Get();
    double speed = a.vel_cmd.Get();
    if (speed == 0 && a.has_last) speed = pos_cmd - a.last_pos_cmd_mm;  // only the sign is used
    a.last_pos_cmd_mm = pos_cmd;
    a.has_last = true;
    out[i].position_mm = a.pos_fb.Get();
    out[i].moving = std::abs(speed) > kMovingSpeedMmS;
    if (out[i].moving) out[i].servo_direction = speed > 0 ? 1 : -1;
  }
  machine.coolant = flood_.Get() ? CoolantState::kFlood : (mist_.Get() ? CoolantState::kMist : CoolantState::kOff);
  machine.compensation_enabled = enable_.Get();
  return true;
}

bool HalCncLink::WriteCompensation(std::span<const double> correction_um) {
  for (std::size_t i = 0; i < axes_.size() && i < correction_um.size(); ++i) {
    const double counts = std::round(correction_um[i] / axes_[i].interface.pulse_equivalent_um);
    if (!std::isfinite(counts) || std::abs(counts) > std::numeric_limits<std::int32_t>::max()) return false;
    axes_[i].counts.Set(static_cast<std::int32_t>(counts));
    axes_[i].correction_um.Set(counts * axes_[i].interface.pulse_equivalent_um);
  }
  return true;
}

void HalCncLink::ReleaseOffsets() {
  for (auto& a : axes_) {
    a.counts.Set(0);
    a.correction_um.Set(0);
  }
}

}  // namespace trueaxis::linuxcnc
