#pragma once
// The predicted tip error applied as a tool length offset
// (docs/tool-thermal.md, "Compensation").
//
// Each cycle the mounted tool's model (kept per tool, with its own
// classifier and lag state restarted at every mounting) predicts the tip
// error e; the desired correction −e goes through runtime::OutputShaper, the
// compensator's limiter (bound, rate limit, quantum with hysteresis). A tool
// change therefore switches the model and ramps the thermal offset from the
// old tool's value to the new one's at ≤ max_rate_um_per_s — never a jump.
// A tool without a model ramps to 0 and says so (`unmodelled`).
//
// Sign (docs/sign-convention.md): correction = −error. A tool that grew by
// g µm has error −g at the tip and needs its length offset lengthened by g:
// offset length = nominal length + correction.
#include <map>
#include <span>
#include <string>

#include "trueaxis/runtime/output_shaper.hpp"
#include "trueaxis/tooltherm/tool_error_model.hpp"
#include "trueaxis/tooltherm/tool_table.hpp"

namespace trueaxis::tooltherm {

struct ToolOffsetOptions {
  // bound 100 µm; max_step_um is set each cycle to max_rate_um_per_s × the time since the last one
  runtime::OutputShaperOptions shaper{100.0, 1.0, 0.25};
  double max_rate_um_per_s = 10.0;  // ramp rate: a 50 µm switch takes 5 s, within a tool change
  double quantum_um = 0.1;
};

struct ToolOffsetCycle {
  int tool = 0;
  double predicted_error_um = 0;
  double desired_correction_um = 0;
  double applied_correction_um = 0;  // what the tool length offset carries this cycle
  bool limited = false;              // applied ≠ desired beyond one quantum (ramping or bounded)
  bool unmodelled = false;
  ThermalInterval interval = ThermalInterval::kStartUp;
};

class ToolOffsetCompensator {
 public:
  ToolOffsetCompensator(std::map<int, ToolErrorModel> models, ToolModelKind kind, ToolOffsetOptions options = {});
  ToolOffsetCompensator(const ToolOffsetCompensator&) = delete;  // the predictors point into models_
  ToolOffsetCompensator& operator=(const ToolOffsetCompensator&) = delete;
  ToolOffsetCycle Cycle(double time_s, int tool, double tv_c, std::span<const double> zone_c = {});

 private:
  std::map<int, ToolErrorModel> models_;
  std::map<int, ToolErrorPredictor> predictors_;
  ToolModelKind kind_;
  ToolOffsetOptions options_;
  runtime::OutputShaperState shaper_;
  int mounted_ = 0;
  double last_time_s_ = 0;
  bool started_ = false;
};

// LinuxCNC tool table line: "T<n> P<n> Z<len> D<dia> ;<comment>" with len = nominal + correction.
std::string LinuxCncToolTableLine(const ToolDescription& tool, double nominal_length_mm, double correction_um);
// G-code a user can run: "G10 L1 P<n> Z<len>" (writes the tool table) then "G43 H<n>" (applies it).
std::string G10ToolOffsetCommand(int tool, double nominal_length_mm, double correction_um);

}  // namespace trueaxis::tooltherm
