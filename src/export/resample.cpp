#include "trueaxis/export/resample.hpp"

#include "trueaxis/core/interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

bool ResampleOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (!std::isnan(spacing_mm) && !(spacing_mm > 0 && std::isfinite(spacing_mm)))
    return fail("--spacing: must be a positive number of mm");
  if (count != 0 && count < 2) return fail("--count: a table needs at least 2 points");
  if (!std::isnan(start_mm) && !std::isfinite(start_mm)) return fail("--start: must be a finite number of mm");
  if (max_points < 2) return fail("max points: must be at least 2");
  if (!std::isnan(range_min_mm) && !std::isnan(range_max_mm) && !(range_max_mm > range_min_mm))
    return fail("--range: the maximum must be greater than the minimum");
  for (const auto& [name, t] : thermal.temperatures_c)
    if (!std::isfinite(t) || t < -50 || t > 150)
      return fail(fmt::format("--temp: {}={} °C is outside −50…150 °C", name, t));
  return true;
}

namespace {

constexpr double kTol = 1e-9;

double NiceSpacing(double span_mm, int max_points) {
  // Smallest 1-2-5 step giving at most max_points points over span.
  for (int exponent = -3; exponent <= 5; ++exponent) {
    for (double mantissa : {1.0, 2.0, 5.0}) {
      const double s = mantissa * std::pow(10.0, exponent);
      if (std::floor(span_mm / s + kTol) + 1 <= max_points) return s;
    }
  }
  return span_mm;
}

std::string Num(double v) { return FormatShortest(std::round(v * 1e9) / 1e9); }
// A correction as a user reads it: to 0.1 µm (the table's file keeps every digit).
std::string Um(double v) { return fmt::format("{:.1f}", v + 0.0); }

}  // namespace

std::vector<double> MakeGrid(const ResampleOptions& o, double valid_min, double valid_max, double reference,
                             const std::string& source) {
  std::string why;
  if (!o.IsValid(&why)) {
    const auto colon = why.find(':');
    throw InputError(source, 0, why.substr(0, colon), why.substr(colon + 2));
  }
  const double lo = std::isnan(o.range_min_mm) ? valid_min : o.range_min_mm;
  const double hi = std::isnan(o.range_max_mm) ? valid_max : o.range_max_mm;
  if (lo < valid_min - 1e-6 || hi > valid_max + 1e-6)
    throw InputError(source, 0, "--range",
                     fmt::format("{}…{} mm reaches beyond where the source is valid ({}…{} mm); "
                                 "a table must not extrapolate the model",
                                 Num(lo), Num(hi), Num(valid_min), Num(valid_max)));
  double spacing = o.spacing_mm;
  double start = o.start_mm;
  int count = o.count;
  if (std::isnan(spacing)) {
    if (count != 0) {
      const double from = std::isnan(start) ? lo : start;
      spacing = (hi - from) / (count - 1);
      if (!(spacing > 0)) throw InputError(source, 0, "--start", "leaves no room for the table below the range end");
    } else {
      spacing = NiceSpacing(hi - lo, o.max_points);
    }
  }
  double outside_tol = 1e-6;  // how far the grid may reach past where the source is valid (mm)
  if (std::isnan(start)) {
    const bool on_reference = !std::isnan(reference) && reference >= lo - kTol && reference <= hi + kTol &&
                              (!std::isnan(o.reference_position_mm) || o.reference_on_grid);
    if (on_reference) {
      // Align on the reference point given (or one the format counts from), inside [lo, hi].
      start = reference - std::floor((reference - lo) / spacing + kTol) * spacing;
    } else {
      // Round positions: the first multiple of the spacing (else of 1, 0.1, 0.01 mm) in the range
      // that keeps as many points as starting at the range's low end; else the low end to 0.001 mm
      // (at most 0.0005 mm beyond where the source is valid: a position, not an extrapolation).
      auto points_from = [&](double from) { return std::floor((hi - from) / spacing + kTol) + 1; };
      const double most = points_from(lo);
      for (double unit : {spacing, 1.0, 0.1, 0.01}) {
        if (unit > spacing + kTol) continue;  // whole mm on a 0.5 mm grid would skip points
        const double from = std::ceil(lo / unit - kTol) * unit;
        if (points_from(from) >= most) {
          start = from;
          break;
        }
      }
      if (std::isnan(start)) {
        start = std::round(lo * 1000) / 1000;
        outside_tol = 5e-4 + kTol;
      }
    }
  }
  if (count == 0) count = static_cast<int>(std::floor((hi - start) / spacing + kTol)) + 1;
  if (count < 2)
    throw InputError(source, 0, "--spacing",
                     fmt::format("{} mm leaves fewer than 2 points in {}…{} mm", Num(spacing), Num(start), Num(hi)));
  if (count > o.max_points)
    throw InputError(source, 0, o.count != 0 ? "--count" : "--spacing",
                     fmt::format("{} points ({} mm step from {} mm) exceed the format's limit of {} points; "
                                 "choose a larger --spacing or a smaller --range",
                                 count, Num(spacing), Num(start), o.max_points));
  const double end = start + spacing * (count - 1);
  if (start < valid_min - outside_tol || end > valid_max + outside_tol)
    throw InputError(source, 0, std::isnan(o.start_mm) ? "--count" : "--start",
                     fmt::format("the table {}…{} mm reaches beyond where the source is valid ({}…{} mm); "
                                 "a table must not extrapolate the model",
                                 Num(start), Num(end), Num(valid_min), Num(valid_max)));
  std::vector<double> grid(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) grid[static_cast<std::size_t>(i)] = std::round((start + spacing * i) * 1e9) / 1e9;
  return grid;
}

namespace {

void ValidRange(const model::GeometricError& g, double* lo, double* hi) {
  if (g.kind == model::GeometricError::Kind::kTable && !g.table_position_mm.empty()) {
    *lo = g.table_position_mm.front();
    *hi = g.table_position_mm.back();
  } else {
    *lo = g.center_mm - std::abs(g.half_span_mm);
    *hi = g.center_mm + std::abs(g.half_span_mm);
  }
}

}  // namespace

// Shared tail: unidirectional reduction and zero at reference.
void FinishResample(ResampleResult& r, const ResampleOptions& o, const std::string& source) {
  auto& t = r.table;
  if (!o.bidirectional) {
    double sum = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      sum += t.forward_um[i] - t.reverse_um[i];
      const double mean = 0.5 * (t.forward_um[i] + t.reverse_um[i]);
      t.forward_um[i] = t.reverse_um[i] = mean;
    }
    t.bidirectional = false;
    t.backlash_um = sum / static_cast<double>(t.size());
  }
  if (o.zero_at_reference) {
    const double ref = t.reference_position_mm;
    if (std::isnan(ref) || ref < t.position_mm.front() - kTol || ref > t.position_mm.back() + kTol)
      throw InputError(source, 0, "--zero-at-reference",
                       fmt::format("the reference point {} mm is outside the table {}…{} mm; give --reference-mm "
                                   "(e.g. the machine reference position) inside it, or --range to cover it",
                                   Num(ref),
                                   Num(t.position_mm.front()), Num(t.position_mm.back())));
    r.zero_shift_um = InterpolateClamped(t.position_mm, t.forward_um, ref);
    for (std::size_t i = 0; i < t.size(); ++i) {
      t.forward_um[i] -= r.zero_shift_um;
      t.reverse_um[i] -= r.zero_shift_um;
    }
    t.provenance.push_back(fmt::format("zero at reference {} mm: {} um subtracted from every value", Num(ref),
                                       Num(r.zero_shift_um)));
  }
  ValidateTable(t, source);
}

std::string MeasuredRangeNote(double first_mm, double last_mm) {
  return fmt::format("measured range (vouched for): {}…{} mm; beyond it the end values are held", Num(first_mm),
                     Num(last_mm));
}

ResampleResult ResampleModel(const model::AxisModel& axis, const ResampleOptions& o, const std::string& source) {
  ResampleResult r;
  double flo, fhi, rlo, rhi;
  ValidRange(axis.directions[0].geometric, &flo, &fhi);
  ValidRange(axis.directions[1].geometric, &rlo, &rhi);
  r.valid_min_mm = std::max(flo, rlo);
  r.valid_max_mm = std::min(fhi, rhi);
  if (axis.HasMeasuredRange()) {  // a table must not reach beyond what was measured
    r.valid_min_mm = std::max(r.valid_min_mm, axis.measured_range_mm[0]);
    r.valid_max_mm = std::min(r.valid_max_mm, axis.measured_range_mm[1]);
  }
  if (!(r.valid_max_mm > r.valid_min_mm))
    throw InputError(source, 0, "axes." + axis.axis,
                     "the forward and reverse models have no common valid range to export");
  const double reference = std::isnan(o.reference_position_mm) ? axis.reference_position_mm : o.reference_position_mm;

  // Thermal state from --temp name=value.
  std::vector<double> key(axis.key_sensors.size(), std::numeric_limits<double>::quiet_NaN());
  double ambient = std::numeric_limits<double>::quiet_NaN();
  double motion_m_per_min = 0;  // the motion-heat input frozen at rest unless given
  int key_given = 0;
  for (const auto& [name, value] : o.thermal.temperatures_c) {
    bool matched = false;
    if (axis.HasMotionHeat() && name == model::kMotionHeatName) {
      if (!(value >= 0) || !std::isfinite(value))
        throw InputError(source, 0, "--temp", fmt::format("{}={}: the motion-heat input is a feed in m/min >= 0",
                                                          model::kMotionHeatName, Num(value)));
      motion_m_per_min = value;
      continue;
    }
    for (std::size_t i = 0; i < axis.key_sensors.size(); ++i)
      if (axis.key_sensors[i] == name) {
        key[i] = value;
        ++key_given;
        matched = true;
      }
    if (!axis.ambient_sensor.empty() && axis.ambient_sensor == name) {
      ambient = value;
      matched = true;
    }
    if (!matched) {
      std::string known;
      for (const auto& s : axis.key_sensors) known += (known.empty() ? "" : ", ") + s;
      if (!axis.ambient_sensor.empty()) known += (known.empty() ? "" : ", ") + axis.ambient_sensor + " (ambient)";
      if (axis.HasMotionHeat()) known += (known.empty() ? "" : ", ") + std::string(model::kMotionHeatName) + " (m/min)";
      throw InputError(source, 0, "--temp",
                       fmt::format("unknown sensor '{}' for axis {}; the model knows: {}", name, axis.axis,
                                   known.empty() ? "no sensors" : known));
    }
  }
  if (key_given > 0 && key_given < static_cast<int>(key.size())) {
    for (std::size_t i = 0; i < key.size(); ++i)
      if (std::isnan(key[i]))
        throw InputError(source, 0, "--temp",
                         fmt::format("missing key sensor '{}': give every key sensor of axis {} or none (cold state)",
                                     axis.key_sensors[i], axis.axis));
  }
  if (key_given == 0)
    for (std::size_t i = 0; i < key.size() && i < axis.baseline_temp_c.size(); ++i) key[i] = axis.baseline_temp_c[i];
  model::ThermalState state;
  state.key_temp_c = key;
  state.ambient_c = ambient;
  state.coolant = o.thermal.coolant;
  state.use_thermal = true;
  state.motion_m_per_min = motion_m_per_min;

  // Total thermal slope per direction at the frozen state: the thermal terms
  // are linear in (Px − x), so the value one millimetre below Px is the slope.
  for (Direction d : {Direction::kForward, Direction::kReverse}) {
    const auto p = model::Predict(axis, axis.reference_position_mm - 1.0, d, state);
    (d == Direction::kForward ? r.tan_beta_forward_um_per_mm : r.tan_beta_reverse_um_per_mm) = p.thermal_um + p.ambient_um;
  }

  auto& t = r.table;
  t.axis = axis.axis;
  t.reference_position_mm = reference;
  t.position_mm = MakeGrid(o, r.valid_min_mm, r.valid_max_mm, reference, source);
  model::ThermalState geometric_only = state;
  geometric_only.use_thermal = false;
  const model::ThermalState& used = o.thermal_in_table ? state : geometric_only;
  for (double x : t.position_mm) {
    t.forward_um.push_back(model::CorrectionUm(model::Predict(axis, x, Direction::kForward, used)));
    t.reverse_um.push_back(model::CorrectionUm(model::Predict(axis, x, Direction::kReverse, used)));
  }
  if (!o.thermal_in_table) {
    t.thermal_tan_beta_um_per_mm = 0.5 * (r.tan_beta_forward_um_per_mm + r.tan_beta_reverse_um_per_mm);
    t.thermal_reference_mm = axis.reference_position_mm;
  }
  std::string temps;
  for (const auto& [name, value] : o.thermal.temperatures_c) temps += fmt::format(" {}={}", name, Num(value));
  if (key_given == 0 && !axis.key_sensors.empty()) {  // the cold state: the keys at the model's baseline
    temps += " cold (no --temp): keys at the model's baseline";
    for (std::size_t i = 0; i < key.size(); ++i) temps += fmt::format(" {}={:.2f}", axis.key_sensors[i], key[i]);
  }
  if (axis.HasMotionHeat() && std::none_of(o.thermal.temperatures_c.begin(), o.thermal.temperatures_c.end(),
                                           [](const auto& t) { return t.first == model::kMotionHeatName; }))
    temps += fmt::format(" {}=0 (at rest)", model::kMotionHeatName);
  t.provenance.push_back(fmt::format("source: model {} axis {}", source, axis.axis));
  if (axis.HasMeasuredRange()) t.provenance.push_back(MeasuredRangeNote(axis.measured_range_mm[0], axis.measured_range_mm[1]));
  t.provenance.push_back(fmt::format("thermal state: coolant {},{} tan_beta fwd {} rev {} um/mm about Px {} mm ({})",
                                     CoolantStateName(o.thermal.coolant), temps.empty() ? " cold (no --temp)" : temps,
                                     Num(r.tan_beta_forward_um_per_mm), Num(r.tan_beta_reverse_um_per_mm),
                                     Num(axis.reference_position_mm),
                                     o.thermal_in_table ? "frozen into the values" : "kept out of the values"));
  FinishResample(r, o, source);
  return r;
}

ResampleResult ResampleMeasurement(const measure::Measurement& m, const ResampleOptions& o) {
  const std::string& source = m.source;
  if (!o.thermal.temperatures_c.empty())
    throw InputError(source, 0, "--temp",
                     "a measurement is exported as measured; freezing a thermal state needs a fitted model (--model)");
  if (m.points.empty()) throw InputError(source, 0, "points", "the measurement has no points");
  // Mean deviation per target and direction; targets closer than 1 nm are one target.
  const auto targets = m.Targets();
  std::vector<double> sum_f(targets.size(), 0), sum_r(targets.size(), 0);
  std::vector<int> n_f(targets.size(), 0), n_r(targets.size(), 0);
  for (const auto& p : m.points) {
    auto it = std::lower_bound(targets.begin(), targets.end(), p.target_mm - 1e-6);
    const std::size_t i = static_cast<std::size_t>(it - targets.begin());
    if (p.direction == Direction::kForward) {
      sum_f[i] += p.deviation_um;
      ++n_f[i];
    } else {
      sum_r[i] += p.deviation_um;
      ++n_r[i];
    }
  }
  std::vector<double> fwd(targets.size()), rev(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (n_f[i] == 0 || n_r[i] == 0)
      throw InputError(source, 0, "direction",
                       fmt::format("target {} mm was measured in one direction only; a table needs both",
                                   Num(targets[i])));
    fwd[i] = -sum_f[i] / n_f[i];  // correction = −mean error
    rev[i] = -sum_r[i] / n_r[i];
  }
  if (targets.size() < 2) throw InputError(source, 0, "target_mm", "a table needs at least 2 targets");

  ResampleResult r;
  r.valid_min_mm = targets.front();
  r.valid_max_mm = targets.back();
  auto& t = r.table;
  t.axis = m.Meta("axis").value_or("");
  t.reference_position_mm = std::isnan(o.reference_position_mm) ? targets.front() : o.reference_position_mm;
  const bool derived = std::isnan(o.start_mm) && std::isnan(o.spacing_mm) && o.count == 0 &&
                       std::isnan(o.range_min_mm) && std::isnan(o.range_max_mm);
  if (derived) {
    if (static_cast<int>(targets.size()) > o.max_points)
      throw InputError(source, 0, "--spacing",
                       fmt::format("{} measured targets exceed the format's limit of {} points; give --spacing to resample",
                                   targets.size(), o.max_points));
    t.position_mm = targets;
    t.forward_um = fwd;
    t.reverse_um = rev;
  } else {
    t.position_mm = MakeGrid(o, r.valid_min_mm, r.valid_max_mm, t.reference_position_mm, source);
    for (double x : t.position_mm) {
      t.forward_um.push_back(InterpolateClamped(targets, fwd, x));
      t.reverse_um.push_back(InterpolateClamped(targets, rev, x));
    }
  }
  t.provenance.push_back(fmt::format("source: measurement {} ({} targets, mean over runs per direction)", source,
                                     targets.size()));
  FinishResample(r, o, source);
  return r;
}

std::string ResampleResult::BriefReport() const {
  const auto& t = table;
  double lo = 0, hi = 0;
  if (t.size() > 0) {
    lo = std::min(*std::min_element(t.forward_um.begin(), t.forward_um.end()),
                  *std::min_element(t.reverse_um.begin(), t.reverse_um.end()));
    hi = std::max(*std::max_element(t.forward_um.begin(), t.forward_um.end()),
                  *std::max_element(t.reverse_um.begin(), t.reverse_um.end()));
  }
  const double step = t.UniformSpacingMm();
  std::string s = fmt::format("axis {}: {} points {}…{} mm{}, {}, correction {}…{} um", t.axis, t.size(),
                              Num(t.position_mm.front()), Num(t.position_mm.back()),
                              std::isnan(step) ? std::string(" (not equidistant)") : fmt::format(" step {} mm", Num(step)),
                              t.bidirectional ? "bidirectional" : fmt::format("unidirectional, backlash {:.1f} um", t.backlash_um),
                              Um(lo), Um(hi));
  if (zero_shift_um != 0) s += fmt::format(", zeroed at reference (shift {} um)", Um(zero_shift_um));
  // Does the table cover the travel the source is valid for? Beyond its ends a controller holds the end values.
  if (t.size() > 0 && valid_max_mm > valid_min_mm &&
      (t.position_mm.front() > valid_min_mm + 1e-3 || t.position_mm.back() < valid_max_mm - 1e-3))
    s += fmt::format("; covers {}…{} mm of the {}…{} mm the source is valid for (the end values hold beyond)",
                     Num(t.position_mm.front()), Num(t.position_mm.back()), Num(valid_min_mm), Num(valid_max_mm));
  return s;
}

}  // namespace trueaxis::exporter
