#pragma once
// VirtualTool: one tool and its holder as a lumped thermal network, for the
// virtual machine (docs/tool-thermal.md, "Virtual tool").
//
// Bodies (nodes): the tool's stick-out in three segments (tip, middle, shank)
// and the holder in two (front, taper). Links: conduction along the tool
// (λ·A/ℓ), the clamp (tool shank ↔ holder front), the holder's own
// conduction, and — while mounted — the taper contact to the spindle nose
// (a boundary at sim::VirtualSpindle::FrontShaftC()). Every segment loses
// heat to the air (more while it turns) and, with coolant on, to the coolant.
// Heat: cutting_heat_share · cutting power into the tip segment.
//
// Truth: the tip moves by Σ α·ℓ·(T − T_std) over the five segments (tool
// stick-out and holder). The segments have time constants from seconds (tip)
// to minutes (holder), so the growth at a given surface temperature differs
// between heating and cooling: the hysteresis seed 001 models.
// Sign (docs/sign-convention.md): the tip grows towards the work (−Z of a
// vertical spindle), so the Z error at the tip is −GrowthUm().
#include <array>

#include "trueaxis/sim/thermal_network.hpp"
#include "trueaxis/tooltherm/tool_table.hpp"

namespace trueaxis::tooltherm {

struct ToolConditions {
  bool mounted = false;        // in the spindle (else in the magazine)
  double nose_c = 20;          // spindle nose temperature (mounted)
  double rpm = 0;
  double cutting_power_w = 0;  // power at the cut (0 = air move / idle)
  bool coolant = false;
  double coolant_c = 20;
  double ambient_c = 20;
};

class VirtualTool {
 public:
  static constexpr int kSegments = 5;  // tip, middle, shank, holder front, holder taper

  VirtualTool(ToolDescription tool, double standard_temp_c, double ambient_c);

  void Advance(double dt_s, const ToolConditions& c);

  double GrowthUm() const;                      // + = longer tool
  double TipErrorUm() const { return -GrowthUm(); }  // Z error at the tip (vertical spindle)
  // Surface temperature at z mm from the tip (linear between segment centres).
  double SurfaceC(double z_from_tip_mm) const;
  double SegmentC(int segment) const { return net_.Temperature(seg_[static_cast<std::size_t>(segment)]); }
  double SegmentFromMm(int segment) const { return from_mm_[static_cast<std::size_t>(segment)]; }
  double SegmentToMm(int segment) const { return to_mm_[static_cast<std::size_t>(segment)]; }
  const ToolDescription& tool() const { return tool_; }

 private:
  ToolDescription tool_;
  double standard_temp_c_;
  sim::ThermalNetwork net_;
  std::size_t ambient_ = 0, nose_ = 0, coolant_ = 0;
  std::array<std::size_t, kSegments> seg_{};
  std::array<std::size_t, kSegments> air_edge_{}, coolant_edge_{};
  std::size_t taper_edge_ = 0;
  std::array<double, kSegments> from_mm_{}, to_mm_{}, area_m2_{}, expansion_{};
  double taper_w_per_k_ = 0;
};

}  // namespace trueaxis::tooltherm
