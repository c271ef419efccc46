#pragma once
// StatusPins: the compensator's state on HAL pins, written by the loop thread after every cycle
// (a CycleObserver: plain stores into HAL memory, no allocation, no lock):
//   out C.alarm           bit    any alarm raised (runtime::Alarm)
//   out C.alarms          s32    the alarm bits (docs/runtime.md; `trueaxis` prints their names)
//   out C.active          bit    a model is in force and compensation is enabled
//   out C.temperatures-ok bit    the temperature snapshot in force was read
//   out C.temperature-age-s float  its age
//   out C.L.clamped       bit    the axis's correction saturates at its bound (alarm too)
#include <vector>

#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/runtime/loop_runner.hpp"

namespace trueaxis::linuxcnc {

class StatusPins : public runtime::CycleObserver {
 public:
  StatusPins(HalComponent& component, const std::vector<std::string>& axis_names);
  void OnCycle(const runtime::CycleStatus& status) override;

 private:
  Pin<bool> alarm_, active_, temperatures_ok_;
  Pin<std::int32_t> alarms_;
  Pin<double> temperature_age_s_;
  std::vector<Pin<bool>> clamped_;
  std::vector<Pin<bool>> thermal_;                 // the thermal part is in use (not geometric only)
  std::vector<Pin<std::int32_t>> fallback_model_;  // the fallback model in use, -1: the model's own
};

}  // namespace trueaxis::linuxcnc
