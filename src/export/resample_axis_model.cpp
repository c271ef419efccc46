#include "trueaxis/export/resample_axis_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

namespace {

std::string Num(double v) { return FormatShortest(std::round(v * 1e9) / 1e9); }

// The model's sensors in Sensors() order, from --temp NAME=°C; every one given, nothing else.
std::vector<double> FrozenSensors(const model::AxisErrorModel& m, const ThermalFreeze& freeze, const std::string& source) {
  const auto& names = m.Sensors();
  const std::string reads = names.empty() ? std::string("no sensors") : fmt::format("{}", fmt::join(names, ", "));
  std::vector<double> values(names.size(), std::numeric_limits<double>::quiet_NaN());
  for (const auto& [name, value] : freeze.temperatures_c) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      throw InputError(source, 0, "--temp",
                       fmt::format("unknown sensor '{}': the model for axis {} reads {}", name, m.Axis(), reads));
    values[static_cast<std::size_t>(it - names.begin())] = value;
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    if (std::isnan(values[i]))
      throw InputError(source, 0, "--temp",
                       fmt::format("missing sensor '{}': the table freezes the model at given temperatures; give "
                                   "--temp {}=DEGREES for every sensor it reads ({})",
                                   names[i], names[i], reads));
  return values;
}

}  // namespace

bool IsConstantAlongAxis(const CompensationTable& t) {
  if (t.size() == 0) return true;
  const double v = t.forward_um.front();
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::abs(t.forward_um[i] - v) > 1e-3 || std::abs(t.reverse_um[i] - v) > 1e-3) return false;
  return true;
}

ResampleResult ResampleAxisErrorModel(const model::AxisErrorModel& m, const ResampleOptions& o, const std::string& source,
                                      const AxisModelValidity& validity) {
  const std::vector<double> sensors = FrozenSensors(m, o.thermal, source);
  if (std::isnan(o.range_min_mm) || std::isnan(o.range_max_mm))
    throw InputError(source, 0, "--range",
                     "required: this model has no position range of its own; give MIN:MAX in mm, the travel the "
                     "table is to cover");
  ResampleResult r;
  r.valid_min_mm = std::isnan(validity.min_mm) ? o.range_min_mm : validity.min_mm;
  r.valid_max_mm = std::isnan(validity.max_mm) ? o.range_max_mm : validity.max_mm;
  auto& t = r.table;
  t.axis = m.Axis();
  t.reference_position_mm = std::isnan(o.reference_position_mm) ? o.range_min_mm : o.reference_position_mm;
  t.thermal_reference_mm = t.reference_position_mm;
  t.position_mm = MakeGrid(o, r.valid_min_mm, r.valid_max_mm, t.reference_position_mm, source);

  // Start-up dynamics, never advanced: lags settled at the given temperatures, no interval history.
  const auto dynamics = std::make_unique<model::AxisModelDynamics>();
  m.ResetDynamics(*dynamics);
  for (double x : t.position_mm) {
    // correction = −error (docs/sign-convention.md)
    t.forward_um.push_back(-m.ErrorUm(x, Direction::kForward, sensors, o.thermal.coolant, *dynamics));
    t.reverse_um.push_back(-m.ErrorUm(x, Direction::kReverse, sensors, o.thermal.coolant, *dynamics));
  }
  for (std::size_t i = 0; i < t.size(); ++i)
    if (!std::isfinite(t.forward_um[i]) || !std::isfinite(t.reverse_um[i]))
      throw InputError(source, 0, "--temp",
                       fmt::format("the model predicts no finite error at {} mm for these temperatures",
                                   Num(t.position_mm[i])));

  std::string temps;
  for (const auto& [name, value] : o.thermal.temperatures_c) temps += fmt::format(" {}={}", name, Num(value));
  t.provenance.push_back(fmt::format("source: {} ({})", m.Describe(), source));
  t.provenance.push_back(fmt::format("thermal state: frozen at{}, coolant {}; model dynamics at start-up (lagged "
                                     "inputs settled at these temperatures, an interval model's start-up prediction)",
                                     temps, CoolantStateName(o.thermal.coolant)));
  if (IsConstantAlongAxis(t))
    t.provenance.push_back(fmt::format("the model's prediction does not change with position: one offset of {} um "
                                       "(correction) over the table",
                                       Num(t.forward_um.front())));
  FinishResample(r, o, source);
  return r;
}

}  // namespace trueaxis::exporter
