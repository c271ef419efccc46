#include "trueaxis/tooltherm/tool_offset.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::tooltherm {

ToolOffsetCompensator::ToolOffsetCompensator(std::map<int, ToolErrorModel> models, ToolModelKind kind,
                                             ToolOffsetOptions options)
    : models_(std::move(models)), kind_(kind), options_(options) {
  std::string why;
  if (!options_.shaper.IsValid(&why)) throw std::invalid_argument("tool offset limiter: " + why);
  if (!(options_.max_rate_um_per_s > 0)) throw std::invalid_argument("tool offset limiter: max_rate_um_per_s must be > 0");
  if (!(options_.quantum_um > 0)) throw std::invalid_argument("tool offset limiter: quantum_um must be > 0");
  for (const auto& [number, model] : models_) predictors_.emplace(number, ToolErrorPredictor(models_.at(number), kind_));
}

ToolOffsetCycle ToolOffsetCompensator::Cycle(double time_s, int tool, double tv_c, std::span<const double> zone_c) {
  ToolOffsetCycle c;
  c.tool = tool;
  const bool restart = tool != mounted_;
  mounted_ = tool;
  auto it = predictors_.find(tool);
  if (it == predictors_.end()) {
    c.unmodelled = true;
  } else {
    c.predicted_error_um = it->second.Push(time_s, tv_c, restart, zone_c);
    c.interval = it->second.interval();
  }
  c.desired_correction_um = -c.predicted_error_um;
  runtime::OutputShaperOptions cycle = options_.shaper;
  // The step allowed this cycle follows the time since the last one (the first cycle: one quantum).
  cycle.max_step_um = started_ ? std::max(options_.max_rate_um_per_s * std::max(time_s - last_time_s_, 0.0), options_.quantum_um)
                               : options_.quantum_um;
  started_ = true;
  last_time_s_ = time_s;
  shaper_ = runtime::ShapeOutput(shaper_, c.desired_correction_um, options_.quantum_um, cycle);
  c.applied_correction_um = runtime::OutputUm(shaper_, options_.quantum_um);
  c.limited = std::abs(c.applied_correction_um - c.desired_correction_um) > options_.quantum_um;
  return c;
}

std::string LinuxCncToolTableLine(const ToolDescription& tool, double nominal_length_mm, double correction_um) {
  return fmt::format("T{0} P{0} Z{1:+.4f} D{2:+.4f} ;{3} thermal {4:+.1f} um", tool.number,
                     nominal_length_mm + correction_um * 1e-3, tool.diameter_mm,
                     tool.name.empty() ? fmt::format("tool {}", tool.number) : tool.name, correction_um);
}

std::string G10ToolOffsetCommand(int tool, double nominal_length_mm, double correction_um) {
  return fmt::format("G10 L1 P{0} Z{1:.4f} (thermal {2:+.1f} um)\nG43 H{0}", tool, nominal_length_mm + correction_um * 1e-3,
                     correction_um);
}

}  // namespace trueaxis::tooltherm
