#pragma once
// Per-axis interface parameters of seed 000's I/O data-interaction unit
// (交互参数: 脉冲当量 δ, 直径/半径编程, 参考点坐标) plus an enable switch.
//
// Units and frames (docs/runtime.md):
//  * The model is fitted in the laser's frame: physical slide position in mm
//    (radius for a lathe cross-slide), errors in µm.
//  * The CNC may report the axis as a DIAMETER (diameter programming): a
//    cross-slide that moves 1 mm radially reports 2 mm, and a compensation
//    input of 2 µm moves the tool 1 µm radially. So for a diameter axis the
//    model position is reported/2 and the value written is 2 × the radial
//    correction.
//  * `position_offset_mm` is added to the (radius) CNC coordinate to obtain
//    the model's coordinate, e.g. when the machine zero was re-referenced
//    after the calibration.
//  * `pulse_equivalent_um` δ is the CNC's output quantum IN CNC UNITS (what
//    is written). The physical quantum is δ for radius axes and δ/2 for
//    diameter axes; every value written is an integer multiple of δ.
#include <cmath>
#include <limits>
#include <string>

namespace trueaxis::runtime {

enum class Programming { kRadius, kDiameter };

struct AxisInterface {
  std::string axis;                 // CNC axis name ("X"); matched to the model's axis name
  double pulse_equivalent_um = 1.0; // δ: output quantum in CNC units, > 0
  Programming programming = Programming::kRadius;
  double position_offset_mm = 0;    // model coordinate = CNC radius coordinate + offset
  // Px override: NaN keeps the model's reference_position_mm (seed 000 "参考点坐标位置的设定").
  double reference_position_mm = std::numeric_limits<double>::quiet_NaN();
  bool enabled = true;              // initial state of this axis's enable switch
  // This axis's bound on |correction| (physical µm), e.g. derived from its fitted model
  // (model::DeriveCompensationBound); NaN: the compensator's common bound (shaper.max_correction_um).
  // Asking for more raises kAlarmCorrectionClamped: saturation is never silent.
  double max_correction_um = std::numeric_limits<double>::quiet_NaN();

  bool IsValid(std::string* why) const;

  // CNC units per physical (radius) unit: 2 for diameter axes.
  double CncScale() const { return programming == Programming::kDiameter ? 2.0 : 1.0; }
  // Physical quantum in µm (the step the slide really moves per output count).
  double PhysicalQuantumUm() const { return pulse_equivalent_um / CncScale(); }
  // Model coordinate of a position reported by the CNC.
  double ModelPositionMm(double cnc_position_mm) const {
    return cnc_position_mm / CncScale() + position_offset_mm;
  }
  // Value to write for a physical (radius) correction.
  double CncCorrectionUm(double physical_correction_um) const { return physical_correction_um * CncScale(); }
};

}  // namespace trueaxis::runtime
