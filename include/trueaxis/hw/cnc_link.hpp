#pragma once
// CncLink: the runtime's only view of a CNC (MISSION M3), in the spirit of a
// ros2_control hardware component: it exports state (per axis machine
// coordinate, servo direction; coolant state) and takes one command per axis
// (the compensation value, written into the CNC's compensation input such as
// the external origin offset through the PMC window).
//
// Implementations: the virtual machine tool in process (sim/), and MODBUS TCP
// against a PMC-window register map (drivers/, docs/protocols.md). The
// runtime cannot tell them apart.
//
// Contract: Read() and WriteCompensation() do not allocate and return false on
// a link fault (timeout, refused, bad reply); the caller decides how to degrade.
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "trueaxis/hw/lifecycle.hpp"

#include "trueaxis/core/coolant.hpp"

namespace trueaxis::hw {

struct AxisState {
  double position_mm = 0;  // machine coordinate exactly as the CNC reports it: a diameter on a
                           // diameter-programmed axis (the runtime converts, docs/runtime.md)
  int servo_direction = 0; // +1 moving/last moved towards +, -1 towards -, 0 not known
  bool moving = false;
  // The path the axis has travelled since the CNC started, both directions counted (a CNC's
  // distance counter): the motion-heat input of a thermal model. NaN when the CNC does not
  // report it (the MODBUS terminal then sums it from the positions it reads, docs/protocols.md).
  double travel_mm = std::numeric_limits<double>::quiet_NaN();
  // The direction of the CNC's programmed (commanded) motion of the axis: +1 towards +, -1 towards
  // -, of the move under way or, at standstill, of the last one; never changed by the
  // compensation's own offset. 0: the CNC does not tell (the runtime then judges the direction
  // from the moving flag, the servo direction and the position, docs/runtime.md step 4).
  int programmed_direction = 0;
  // The compensation the CNC applies now (µm, CNC units, as written by WriteCompensation). The
  // compensator picks the machine up there after a start or a lost link, so its output never jumps
  // (docs/runtime.md). NaN when the CNC does not report it (the loop then starts from zero).
  double applied_um = std::numeric_limits<double>::quiet_NaN();
};

struct CncState {
  CoolantState coolant = CoolantState::kOff;
  bool compensation_enabled = false;  // the CNC-side enable (parameter / PMC bit)
};

class CncLink : public HardwareLifecycle {
 public:
  virtual ~CncLink() = default;
  virtual std::size_t AxisCount() const = 0;
  virtual std::string AxisName(std::size_t axis) const = 0;
  // Fills axes[0..AxisCount()) and machine. False on link fault.
  virtual bool Read(std::span<AxisState> axes, CncState& machine) = 0;
  // Writes one compensation value per axis, in µm, as the CORRECTION to add to
  // the commanded position (docs/sign-convention.md), in the CNC's own units
  // (diameter on a diameter-programmed axis). False on link fault.
  virtual bool WriteCompensation(std::span<const double> correction_um) = 0;
};

}  // namespace trueaxis::hw
