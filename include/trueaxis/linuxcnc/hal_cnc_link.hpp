#pragma once
// HalCncLink: LinuxCNC seen through HAL pins as an hw::CncLink, so the one compensator
// (runtime::Step, the same as `trueaxis run` and the MODBUS terminal) drives a LinuxCNC
// machine (docs/linuxcnc.md). Pins of component C, per axis L (lower case):
//
//   in   C.L.pos-cmd   float  commanded position (joint.N.pos-cmd: includes the external offset), mm
//   in   C.L.pos-fb    float  feedback position (joint.N.pos-fb): the model's position, mm
//   in   C.L.eoffset   float  ← axis.L.eoffset, the offset applied now (mm). The direction and the
//                             moving flag come from the PROGRAMMED motion, pos-cmd − eoffset between
//                             reads: the offset's own µm moves must never flip the direction model
//                             (it would limit-cycle by the reversal value, docs/runtime.md); it is
//                             reported as the programmed direction, held while the axis stands
//   out  C.L.eoffset-counts  s32    → axis.L.eoffset-counts
//   in   C.L.eoffset-request float  ← axis.L.eoffset-request: the offset LinuxCNC holds (mm)
//   out  C.L.eoffset-scale   float  → axis.L.eoffset-scale (mm per count = δ / 1000)
//   out  C.L.eoffset-enable  bit    → axis.L.eoffset-enable (true while the component runs)
//   out  C.L.correction-um   float  the correction the axis holds (CNC units, µm)
//   in   C.enable           bit    the operator's switch (a panel button, an M-code through
//                             motion.digital-out-NN): off → every axis ramps to zero
//   in   C.machine-on       bit    ← motion.motion-enabled: off → no delta is sent (LinuxCNC would
//                             drop it) and the axes ramp to zero like enable off
//   in   C.coolant-flood, C.coolant-mist  bit  ← iocontrol.0.coolant-flood / -mist
//
// The correction reaches the joints through LinuxCNC's external offsets, which its planner
// applies within the axis's velocity/acceleration reserve ([AXIS_L] OFFSET_AV_RATIO).
// LinuxCNC takes eoffset-counts as DELTAS, and drops the deltas that arrive while the machine is
// off or not homed (motion/control.c), and clears the offset at machine on. So the counts are not
// the correction: each write adds (target − what LinuxCNC holds, read back on eoffset-request) to
// the counts, which brings the offset to the target whatever was dropped. No delta is sent while
// C.machine-on is off, so the counts do not run away; the write
// period must exceed the servo period (LinuxCNC has taken the previous delta by then).
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/runtime/axis_interface.hpp"

namespace trueaxis::linuxcnc {

class HalCncLink : public hw::CncLink {
 public:
  // Creates the pins on `component` (before its Ready). `interfaces[i]` gives axis i's name and
  // pulse equivalent δ (the eoffset count).
  HalCncLink(HalComponent& component, std::vector<runtime::AxisInterface> interfaces);

  std::size_t AxisCount() const override { return axes_.size(); }
  std::string AxisName(std::size_t axis) const override { return axes_[axis].interface.axis; }
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override;
  bool WriteCompensation(std::span<const double> correction_um) override;
  // Every eoffset to zero counts (the component stops: LinuxCNC ramps the offsets out).
  void ReleaseOffsets();
  bool CncEnable() const { return enable_.Get() && machine_on_.Get(); }
  bool MachineOn() const { return machine_on_.Get(); }
  // The inputs a record of the machine needs (each axis's pos-fb, machine-on) not netted yet, by
  // pin name ("trueaxis.x.pos-fb").
  std::vector<std::string> StatePinsNotNetted() const;

  // A programmed move of less than this between two reads is "standing" (mm): above the noise of
  // reading pos-cmd and eoffset a servo period apart.
  static constexpr double kMovingStepMm = 5e-4;

 private:
  struct Axis {
    runtime::AxisInterface interface;
    Pin<double> pos_cmd, pos_fb, eoffset_mm;
    Pin<std::int32_t> counts;
    Pin<double> scale, correction_um, request_mm;
    std::int64_t counts_out = 0;
    Pin<bool> offset_enable;
    double last_programmed_mm = 0;
    bool has_last = false;
    int last_direction = 0;  // of the last programmed move (+1/−1; 0 before the first): reported while standing
  };
  std::string prefix_;  // "<component>."
  std::vector<Axis> axes_;
  Pin<bool> enable_, machine_on_, flood_, mist_;
};

// "X" → "x": LinuxCNC's axis pins use lower-case letters (axis.x.eoffset-counts).
std::string HalAxisLetter(const std::string& axis_name);

}  // namespace trueaxis::linuxcnc
