#include "trueaxis/pitch/error_table.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/interpolation.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::pitch {

namespace {

constexpr double kGridTolMm = 1e-3;  // 1 µm: positions printed to the µm are on the grid

std::string Num(double v) { return FormatShortest(std::round(v * 1e6) / 1e6); }

// Grid positions reference + k·spacing inside [lo, hi] (within the tolerance).
std::vector<double> GridInside(double reference, double spacing, double lo, double hi) {
  std::vector<double> g;
  const long long k0 = static_cast<long long>(std::ceil((lo - reference) / spacing - kGridTolMm / spacing));
  for (long long k = k0;; ++k) {
    const double x = reference + static_cast<double>(k) * spacing;
    if (x > hi + kGridTolMm) break;
    g.push_back(std::round(x * 1e6) / 1e6);
  }
  return g;
}

}  // namespace

bool PitchErrorTable::OutsideVouchedRange(double x_mm) const {
  return x_mm < VouchedFromMm() - model::kMeasuredRangeToleranceMm || x_mm > VouchedToMm() + model::kMeasuredRangeToleranceMm;
}

std::optional<std::string> MeasuredRangeWarning(const PitchErrorTable& t, const std::string& source) {
  if (t.HasMeasuredRange()) return std::nullopt;
  return fmt::format("{}: the file does not say which range axis {} was measured over (no '# measured_from_mm:' / "
                     "'# measured_to_mm:' lines); the table's ends {}…{} mm are taken as that range",
                     source, t.axis, Num(t.position_mm.front()), Num(t.position_mm.back()));
}

std::optional<std::string> UncoveredTravelWarning(double first_mm, double last_mm, double travel_mm,
                                                  const std::string& source) {
  if (!std::isfinite(travel_mm)) return std::nullopt;
  std::string zones;
  const double tol = model::kMeasuredRangeToleranceMm;
  if (first_mm > tol) zones += fmt::format("0…{} mm", Num(first_mm));
  if (last_mm < travel_mm - tol) zones += fmt::format("{}{}…{} mm", zones.empty() ? "" : " and ", Num(last_mm), Num(travel_mm));
  if (zones.empty()) return std::nullopt;
  return fmt::format("{}: the run measured {}…{} mm of the travel 0…{} mm; the table vouches for nothing in {} — "
                     "there the end values are held and `run` raises outside_measured_range. Measure the whole "
                     "travel (trueaxis sim fine, docs/pitch-error-file.md)",
                     source, Num(first_mm), Num(last_mm), Num(travel_mm), zones);
}

TableLookup LookupError(const PitchErrorTable& t, double x_mm, Direction direction) {
  const auto& ys = direction == Direction::kForward ? t.error_up_um : t.error_down_um;
  TableLookup r;
  r.outside = t.OutsideVouchedRange(x_mm);
  // Beyond the vouched range the value at its end is held (never the slope towards a sample past it).
  r.error_um = InterpolateClamped(t.position_mm, ys, std::clamp(x_mm, t.VouchedFromMm(), t.VouchedToMm()));
  return r;
}

double CorrectionUm(const PitchErrorTable& table, double x_mm, int direction) {
  return -LookupError(table, x_mm, direction < 0 ? Direction::kReverse : Direction::kForward).error_um;
}

void ValidatePitchTable(const PitchErrorTable& t, const std::string& source) {
  if (!(t.lead_mm >= 0.5 && t.lead_mm <= 200)) throw InputError(source, 0, "lead_mm", fmt::format("{} is outside 0.5…200 mm", t.lead_mm));
  if (t.samples_per_lead < 1 || t.samples_per_lead > 64)
    throw InputError(source, 0, "samples_per_lead", fmt::format("{} is outside 1…64", t.samples_per_lead));
  if (t.position_mm.size() < 2) throw InputError(source, 0, "position_mm", "a table needs at least 2 points");
  if (t.error_up_um.size() != t.size() || t.error_down_um.size() != t.size())
    throw InputError(source, 0, "error_up_um", "the columns differ in length");
  const double s = t.SpacingMm();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double x = t.position_mm[i];
    if (auto why = ImplausiblePositionMm(x)) throw InputError(source, 0, fmt::format("position_mm[{}]", i), *why);
    for (const auto* col : {&t.error_up_um, &t.error_down_um})
      if (auto why = ImplausibleDeviationUm((*col)[i]))
        throw InputError(source, 0, fmt::format("{}[{}]", col == &t.error_up_um ? "error_up_um" : "error_down_um", i), *why);
    const double k = (x - t.reference_mm) / s;
    if (std::abs(k - std::round(k)) * s > kGridTolMm)
      throw InputError(source, 0, fmt::format("position_mm[{}]", i),
                       fmt::format("{} mm is not on the grid {} + k·{} mm (lead {} mm / {} per lead)", Num(x),
                                   Num(t.reference_mm), Num(s), Num(t.lead_mm), t.samples_per_lead));
    if (i > 0 && std::abs(x - t.position_mm[i - 1] - s) > kGridTolMm)
      throw InputError(source, 0, fmt::format("position_mm[{}]", i),
                       fmt::format("{} mm follows {} mm: the samples must be {} mm apart (lead {} mm / {} per lead), "
                                   "ascending, none missing",
                                   Num(x), Num(t.position_mm[i - 1]), Num(s), Num(t.lead_mm), t.samples_per_lead));
  }
  if (std::isnan(t.measured_from_mm) != std::isnan(t.measured_to_mm))
    throw InputError(source, 0, std::isnan(t.measured_from_mm) ? "measured_from_mm" : "measured_to_mm",
                     "give both ends of the measured range, or neither");
  if (t.HasMeasuredRange()) {
    for (const auto& [v, field] : {std::pair{t.measured_from_mm, "measured_from_mm"}, std::pair{t.measured_to_mm, "measured_to_mm"}})
      if (auto why = ImplausiblePositionMm(v)) throw InputError(source, 0, field, *why);
    if (!(t.measured_from_mm < t.measured_to_mm))
      throw InputError(source, 0, "measured_to_mm",
                       fmt::format("{} mm is not beyond measured_from_mm {} mm", Num(t.measured_to_mm), Num(t.measured_from_mm)));
    if (t.measured_from_mm < t.position_mm.front() - kGridTolMm || t.measured_to_mm > t.position_mm.back() + kGridTolMm)
      throw InputError(source, 0, "measured_from_mm",
                       fmt::format("the measured range {}…{} mm reaches beyond the table's samples {}…{} mm: a table "
                                   "must cover the range it vouches for",
                                   Num(t.measured_from_mm), Num(t.measured_to_mm), Num(t.position_mm.front()),
                                   Num(t.position_mm.back())));
  }
}

PitchErrorTable TableFromMeasurement(const measure::Measurement& m, const TableFromMeasurementOptions& o) {
  const std::string& source = m.source;
  double lead = o.lead_mm;
  if (!(lead > 0)) {
    auto meta = m.Meta("lead_mm");
    if (!meta) throw InputError(source, 0, "lead_mm", "the screw lead is needed: give --lead-mm or a '# lead_mm:' line");
    auto v = ParseDouble(Trim(*meta));
    if (!v || !std::isfinite(*v))
      throw InputError(source, m.MetaLine("lead_mm"), "lead_mm", fmt::format("'{}' is not a number of mm", *meta));
    lead = *v;
  }
  const analysis::Evaluation ev = analysis::Evaluate(m);
  std::vector<double> xs, up, down;
  for (const auto& tr : ev.targets) {
    xs.push_back(tr.target_mm);
    up.push_back(tr.mean_up_um);
    down.push_back(tr.mean_down_um);
  }
  PitchErrorTable t;
  t.axis = m.Meta("axis").value_or("X");
  t.lead_mm = lead;
  t.samples_per_lead = o.samples_per_lead;
  double ref = o.reference_mm;
  if (std::isnan(ref)) {
    auto meta = m.Meta("reference_mm");
    auto v = meta ? ParseDouble(Trim(*meta)) : std::nullopt;
    if (meta && (!v || !std::isfinite(*v)))
      throw InputError(source, m.MetaLine("reference_mm"), "reference_mm", fmt::format("'{}' is not a position in mm", *meta));
    ref = v ? *v : xs.front();
  }
  t.reference_mm = ref;
  const double spacing = t.SpacingMm();
  double max_gap = 0;
  for (std::size_t i = 1; i < xs.size(); ++i) max_gap = std::max(max_gap, xs[i] - xs[i - 1]);
  if (max_gap > spacing + kGridTolMm)
    throw InputError(source, 0, "target_mm",
                     fmt::format("targets up to {} mm apart cannot give a table every {} mm (lead {} mm / {} per lead): "
                                 "the lead's harmonics alias; measure at lead spacing or finer (trueaxis sim fine, "
                                 "docs/pitch-error-file.md)",
                                 Num(max_gap), Num(spacing), Num(lead), o.samples_per_lead));
  int on_target = 0, held = 0;
  // The grid over the measured range: an end target off the grid brings the grid point beyond it.
  std::vector<double> grid = GridInside(ref, spacing, xs.front(), xs.back());
  if (grid.empty() || grid.front() > xs.front() + kGridTolMm)
    grid.insert(grid.begin(), std::round((grid.empty() ? xs.front() : grid.front() - spacing) * 1e6) / 1e6);
  if (grid.back() < xs.back() - kGridTolMm) grid.push_back(std::round((grid.back() + spacing) * 1e6) / 1e6);
  for (double x : grid) {
    t.position_mm.push_back(x);
    t.error_up_um.push_back(InterpolateClamped(xs, up, x));
    t.error_down_um.push_back(InterpolateClamped(xs, down, x));
    const auto it = std::lower_bound(xs.begin(), xs.end(), x - kGridTolMm);
    if (it != xs.end() && std::abs(*it - x) <= kGridTolMm) ++on_target;
    else if (x < xs.front() || x > xs.back()) ++held;
  }
  if (t.size() < 2)
    throw InputError(source, 0, "target_mm",
                     fmt::format("the measured range {}…{} mm holds fewer than 2 points of the grid {} + k·{} mm",
                                 Num(xs.front()), Num(xs.back()), Num(ref), Num(spacing)));
  t.measured_from_mm = xs.front();
  t.measured_to_mm = xs.back();
  t.provenance.push_back(fmt::format("source: measurement {} ({} targets, {} runs, mean per target and direction)", source,
                                     xs.size(), ev.runs));
  const int between = static_cast<int>(t.size()) - on_target - held;
  std::string how = fmt::format("{} of {} samples on measured targets", on_target, t.size());
  if (between > 0) how += fmt::format(", {} linear between neighbours", between);
  if (held > 0) how += fmt::format(", {} beyond an end target (its mean held)", held);
  t.provenance.push_back(how);
  ValidatePitchTable(t, source);
  return t;
}

PitchErrorTable TableFromModel(const model::AxisModel& axis, double lead_mm, int samples_per_lead,
                               const exporter::ThermalFreeze& freeze, const std::string& source) {
  exporter::ResampleOptions o;
  o.spacing_mm = lead_mm / samples_per_lead;
  o.max_points = 1 << 20;  // the error file has no controller's limit
  o.thermal = freeze;
  const exporter::ResampleResult rr = exporter::ResampleModel(axis, o, source);
  PitchErrorTable t;
  t.axis = axis.axis;
  t.lead_mm = lead_mm;
  t.samples_per_lead = samples_per_lead;
  t.reference_mm = axis.reference_position_mm;
  t.position_mm = rr.table.position_mm;
  for (std::size_t i = 0; i < rr.table.size(); ++i) {
    t.error_up_um.push_back(-rr.table.forward_um[i]);
    t.error_down_um.push_back(-rr.table.reverse_um[i]);
  }
  t.provenance = rr.table.provenance;
  // The model's valid range (its measured range when it records one) holds the grid: the table vouches for its span.
  t.measured_from_mm = t.position_mm.front();
  t.measured_to_mm = t.position_mm.back();
  ValidatePitchTable(t, source);
  return t;
}

exporter::ResampleResult ResamplePitchTable(const PitchErrorTable& t, const exporter::ResampleOptions& o,
                                            const std::string& source) {
  exporter::ResampleResult r;
  r.valid_min_mm = t.VouchedFromMm();
  r.valid_max_mm = t.VouchedToMm();
  auto& ct = r.table;
  ct.axis = t.axis;
  ct.reference_position_mm = std::isnan(o.reference_position_mm) ? t.reference_mm : o.reference_position_mm;
  const bool derived = std::isnan(o.start_mm) && std::isnan(o.spacing_mm) && o.count == 0 &&
                       std::isnan(o.range_min_mm) && std::isnan(o.range_max_mm);
  if (derived) {
    if (static_cast<int>(t.size()) > o.max_points) {
      // The smallest whole number of samples per controller point that fits.
      const int every = static_cast<int>((t.size() - 1 + o.max_points - 2) / (o.max_points - 1));
      throw InputError(source, 0, "--spacing",
                       fmt::format("{} samples ({} mm apart, lead {} mm) exceed the format's limit of {} points; nothing "
                                   "is truncated. Resample with --spacing {} (one controller point every {} samples; the "
                                   "controller interpolates between them) or split the axis with --range",
                                   t.size(), Num(t.SpacingMm()), Num(t.lead_mm), o.max_points,
                                   Num(t.SpacingMm() * every), every));
    }
    ct.position_mm = t.position_mm;
    for (std::size_t i = 0; i < t.size(); ++i) {
      ct.forward_um.push_back(-t.error_up_um[i]);
      ct.reverse_um.push_back(-t.error_down_um[i]);
    }
  } else {
    ct.position_mm = exporter::MakeGrid(o, r.valid_min_mm, r.valid_max_mm, ct.reference_position_mm, source);
    double worst = 0;  // what the coarser grid loses at the table's own samples
    for (double x : ct.position_mm) {
      ct.forward_um.push_back(CorrectionUm(t, x, 1));
      ct.reverse_um.push_back(CorrectionUm(t, x, -1));
    }
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double x = t.position_mm[i];
      if (x < ct.position_mm.front() || x > ct.position_mm.back()) continue;
      auto at = [&](const std::vector<double>& ys) { return InterpolateClamped(ct.position_mm, ys, x); };
      worst = std::max({worst, std::abs(at(ct.forward_um) + t.error_up_um[i]), std::abs(at(ct.reverse_um) + t.error_down_um[i])});
    }
    ct.provenance.push_back(fmt::format("resampled from {} pitch samples every {} mm: up to {} um lost at the samples "
                                        "between the controller's points",
                                        t.size(), Num(t.SpacingMm()), fmt::format("{:.3f}", worst)));
  }
  ct.provenance.push_back(fmt::format("source: pitch error file {} (lead {} mm, {} per lead)", source, Num(t.lead_mm),
                                      t.samples_per_lead));
  ct.provenance.push_back(t.HasMeasuredRange() ? exporter::MeasuredRangeNote(t.measured_from_mm, t.measured_to_mm)
                                               : fmt::format("measured range unknown (the pitch error file does not "
                                                             "record it): the table's ends {}…{} mm are taken",
                                                             Num(t.position_mm.front()), Num(t.position_mm.back())));
  for (const auto& p : t.provenance) ct.provenance.push_back(p);
  exporter::FinishResample(r, o, source);
  return r;
}

double MaxInterpolationErrorUm(const PitchErrorTable& table, const measure::Measurement& fine) {
  const analysis::Evaluation ev = analysis::Evaluate(fine);
  double worst = 0;
  for (const auto& tr : ev.targets) {
    if (tr.target_mm < table.VouchedFromMm() - kGridTolMm || tr.target_mm > table.VouchedToMm() + kGridTolMm) continue;
    worst = std::max({worst, std::abs(tr.mean_up_um - LookupError(table, tr.target_mm, Direction::kForward).error_um),
                      std::abs(tr.mean_down_um - LookupError(table, tr.target_mm, Direction::kReverse).error_um)});
  }
  return worst;
}

SamplesPerLeadChoice ChooseSamplesPerLead(const measure::Measurement& m, const TableFromMeasurementOptions& base,
                                          double tolerance_um) {
  SamplesPerLeadChoice choice;
  // Default: the run's own scatter, one σ (R↑ and R↓ are 4 s; the bidirectional R would add the reversal).
  const analysis::AxisResult iso = analysis::Evaluate(m).axis;
  choice.tolerance_um = std::isfinite(tolerance_um) ? tolerance_um : std::max(0.5, 0.25 * std::max(iso.R_up_um, iso.R_down_um));
  bool any = false;
  for (int n = 1; n <= 64; ++n) {
    TableFromMeasurementOptions o = base;
    o.samples_per_lead = n;
    PitchErrorTable table;
    try {
      table = TableFromMeasurement(m, o);
    } catch (const InputError&) {
      if (!any) throw;  // not even once per lead: the run's own error says why
      break;            // the targets are further apart than this spacing: the densest is the last one
    }
    any = true;
    choice.samples_per_lead = n;
    choice.interpolation_error_um = MaxInterpolationErrorUm(table, m);
    if (choice.interpolation_error_um <= choice.tolerance_um) return choice;
  }
  choice.within_tolerance = false;
  return choice;
}

std::string SamplesPerLeadChoice::Describe() const {
  return within_tolerance
             ? fmt::format("{} sample(s) per lead: the fewest whose table meets the run's mean deviations within {:.3f} um "
                           "(max {:.3f} um)",
                           samples_per_lead, tolerance_um, interpolation_error_um)
             : fmt::format("{} samples per lead, as dense as the run's targets allow, still {:.3f} um from its mean "
                           "deviations (tolerance {:.3f} um): measure with targets closer together",
                           samples_per_lead, interpolation_error_um, tolerance_um);
}

}  // namespace trueaxis::pitch
