#include "trueaxis/linuxcnc/hal_cnc_link.hpp"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <limits>

namespace trueaxis::linuxcnc {

std::string HalAxisLetter(const std::string& axis_name) {
  std::string s = axis_name;
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

HalCncLink::HalCncLink(HalComponent& component, std::vector<runtime::AxisInterface> interfaces)
    : prefix_(component.name() + ".") {
  for (auto& it : interfaces) {
    const std::string l = HalAxisLetter(it.axis);
    Axis a;
    a.interface = it;
    a.pos_cmd = component.FloatPin(l + ".pos-cmd", PinDirection::kIn);
    a.pos_fb = component.FloatPin(l + ".pos-fb", PinDirection::kIn);
    a.eoffset_mm = component.FloatPin(l + ".eoffset", PinDirection::kIn);
    a.counts = component.S32Pin(l + ".eoffset-counts", PinDirection::kOut);
    a.request_mm = component.FloatPin(l + ".eoffset-request", PinDirection::kIn);
    a.scale = component.FloatPin(l + ".eoffset-scale", PinDirection::kOut);
    a.offset_enable = component.BitPin(l + ".eoffset-enable", PinDirection::kOut);
    a.correction_um = component.FloatPin(l + ".correction-um", PinDirection::kOut);
    a.scale.Set(it.pulse_equivalent_um / 1000.0);  // mm per count
    a.offset_enable.Set(true);
    axes_.push_back(std::move(a));
  }
  enable_ = component.BitPin("enable", PinDirection::kIn);
  machine_on_ = component.BitPin("machine-on", PinDirection::kIn);
  flood_ = component.BitPin("coolant-flood", PinDirection::kIn);
  mist_ = component.BitPin("coolant-mist", PinDirection::kIn);
}

bool HalCncLink::Read(std::span<hw::AxisState> out, hw::CncState& machine) {
  for (std::size_t i = 0; i < axes_.size() && i < out.size(); ++i) {
    Axis& a = axes_[i];
    const double programmed = a.pos_cmd.Get() - a.eoffset_mm.Get();
    const double step = a.has_last ? programmed - a.last_programmed_mm : 0.0;
    a.last_programmed_mm = programmed;
    a.has_last = true;
    out[i].position_mm = a.pos_fb.Get();
    out[i].moving = std::abs(step) > kMovingStepMm;
    if (out[i].moving) a.last_direction = step > 0 ? 1 : -1;
    // Where the program last moved the axis, also while it stands: the programmed direction (the
    // runtime takes it on every read; pos-fb carries the offset's own ramp, which is no move).
    out[i].servo_direction = a.last_direction;
    out[i].programmed_direction = a.last_direction;
  }
  machine.coolant = flood_.Get() ? CoolantState::kFlood : (mist_.Get() ? CoolantState::kMist : CoolantState::kOff);
  machine.compensation_enabled = CncEnable();
  return true;
}

bool HalCncLink::WriteCompensation(std::span<const double> correction_um) {
  const bool accepting = machine_on_.Get();  // LinuxCNC drops deltas while the machine is off
  for (std::size_t i = 0; i < axes_.size() && i < correction_um.size(); ++i) {
    Axis& a = axes_[i];
    const double delta_um = a.interface.pulse_equivalent_um;
    const double target = std::round(correction_um[i] / delta_um);
    if (!std::isfinite(target) || std::abs(target) > 1e9) return false;
    const double held = std::round(a.request_mm.Get() * 1000.0 / delta_um);  // what LinuxCNC holds, counts
    if (accepting && std::isfinite(held)) {
      a.counts_out += static_cast<std::int64_t>(target - held);
      // The pin is s32; LinuxCNC takes differences, so wrapping around keeps every delta right.
      a.counts.Set(static_cast<std::int32_t>(static_cast<std::uint32_t>(a.counts_out & 0xffffffff)));
    }
    a.correction_um.Set(target * delta_um);
  }
  return true;
}

void HalCncLink::ReleaseOffsets() {
  const double zero[32] = {};
  WriteCompensation(std::span<const double>(zero, std::min<std::size_t>(axes_.size(), 32)));
}

std::vector<std::string> HalCncLink::StatePinsNotNetted() const {
  std::vector<std::string> out;
  for (const auto& a : axes_)
    if (!a.pos_fb.Linked()) out.push_back(prefix_ + HalAxisLetter(a.interface.axis) + ".pos-fb");
  if (!machine_on_.Linked()) out.push_back(prefix_ + "machine-on");
  return out;
}

}  // namespace trueaxis::linuxcnc
