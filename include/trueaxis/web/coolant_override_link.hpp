#pragma once
// CoolantOverrideLink: a CncLink in front of another that, while an override is set, reports the
// forced coolant state instead of the CNC's (the web page's coolant switch: e.g. a coolant line
// the PMC does not report). Everything else passes through. The override may be changed from any
// thread; Read takes it without a lock (an atomic int).
#include <atomic>
#include <optional>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/hw/cnc_link.hpp"

namespace trueaxis::web {

class CoolantOverrideLink : public hw::CncLink {
 public:
  explicit CoolantOverrideLink(hw::CncLink& inner) : inner_(inner) {}
  void SetOverride(std::optional<CoolantState> state) { forced_.store(state ? static_cast<int>(*state) : -1); }
  std::optional<CoolantState> Override() const { return CoolantStateFromCode(forced_.load()); }

  std::size_t AxisCount() const override { return inner_.AxisCount(); }
  std::string AxisName(std::size_t axis) const override { return inner_.AxisName(axis); }
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override {
    const bool ok = inner_.Read(axes, machine);
    if (const auto forced = Override()) machine.coolant = *forced;
    return ok;
  }
  bool WriteCompensation(std::span<const double> correction_um) override { return inner_.WriteCompensation(correction_um); }

 private:
  hw::CncLink& inner_;
  std::atomic<int> forced_{-1};
};

}  // namespace trueaxis::web
