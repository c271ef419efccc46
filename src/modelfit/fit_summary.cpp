#include "trueaxis/modelfit/fit_summary.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace trueaxis::model {
namespace {

std::string SummaryNum(double v, int decimals = 3) {
  if (std::isnan(v)) return "–";
  return fmt::format("{:.{}f}", v, decimals);
}

nlohmann::json JsonNum(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

const char* KindText(GeometricError::Kind k) { return k == GeometricError::Kind::kTable ? "table" : "polynomial"; }

std::string GeometricText(const DirectionFitStats& d) {
  if (d.kind == GeometricError::Kind::kTable)
    return fmt::format("table of {} points (CV {} µm)", d.targets, SummaryNum(d.geometric_cv_rms_um));
  return fmt::format("degree {} (CV {} µm)", d.degree.degree, SummaryNum(d.geometric_cv_rms_um));
}

}  // namespace

std::string FitSummary::BriefReport() const {
  std::string out;
  for (const auto& a : axes) {
    out += fmt::format("axis {}: Er(x) forward {}, reverse {}", a.axis, GeometricText(a.directions[0]),
                       GeometricText(a.directions[1]));
    if (a.thermal_fitted)
      out += fmt::format("; keys {} (thermal CV {} µm, {} µm without); Px {} mm; ρ {} µm/mm/°C",
                         a.key_sensors.empty() ? std::string("none") : fmt::format("{}", fmt::join(a.key_sensors, ", ")),
                         SummaryNum(a.thermal_cv_rms_um), SummaryNum(a.no_thermal_cv_rms_um), SummaryNum(a.reference_position_mm, 1),
                         SummaryNum(a.rho_um_per_mm_per_c, 5));
    if (a.thermal_fitted && !a.lag_reason.empty()) out += fmt::format("; key lag τ {} s", SummaryNum(a.key_lag_s, 0));
    if (a.thermal_fitted && a.motion_lag_s > 0) out += fmt::format("; motion heat τ {} s", SummaryNum(a.motion_lag_s, 0));
    if (a.thermal_fitted && a.key_offsets) out += "; each key's own pivot";
    if (!a.thermal_fitted) out += "; geometric only";
    for (const auto& n : a.fallback_notes) out += "\n  " + n;
    const StateFitStats* worst = nullptr;
    for (const auto& s : a.states)
      if (!worst || s.residual_rms_um > worst->residual_rms_um) worst = &s;
    if (worst)
      out += fmt::format("\n  worst state: {} residual RMS {} µm, max {} µm (uncorrected RMS {} µm)", worst->label,
                         SummaryNum(worst->residual_rms_um), SummaryNum(worst->residual_max_um), SummaryNum(worst->uncorrected_rms_um));
    out += "\n";
    if (!a.diagnosis.states.empty()) out += ResidualDiagnosisBrief(a.diagnosis);
  }
  if (!warnings.empty()) out += fmt::format("{} warning(s):\n", warnings.size());
  for (const auto& w : warnings) out += "  warning: " + w + "\n";
  return out;
}

std::string FitSummary::FullReport() const {
  std::string out;
  for (const auto& a : axes) {
    out += fmt::format("=== axis {} ===\n", a.axis);
    out += fmt::format("cold state: {}\n", a.cold_source);
    for (int d = 0; d < 2; ++d) {
      const auto& ds = a.directions[d];
      out += fmt::format("Er(x) {}: {} targets, {} run(s), {}; fit RMS {} µm, LOTO CV {} µm, table CV {} µm\n",
                         d == 0 ? "forward (+)" : "reverse (−)", ds.targets, ds.runs, KindText(ds.kind),
                         SummaryNum(ds.geometric_fit_rms_um), SummaryNum(ds.geometric_cv_rms_um), SummaryNum(ds.table_cv_rms_um));
      out += fmt::format("  {}\n", ds.choice);
      if (!ds.degree.candidates.empty()) {
        out += "  degree  fit RMS µm  CV RMS µm\n";
        for (const auto& c : ds.degree.candidates)
          out += fmt::format("  {:>6}  {:>10}  {:>9}{}\n", c.degree, SummaryNum(c.fit_rms_um), SummaryNum(c.cv_rms_um),
                             c.degree == ds.degree.degree && ds.kind == GeometricError::Kind::kPolynomial ? "  ← chosen" : "");
        out += fmt::format("  rule: {}\n", ds.degree.rule);
      }
    }
    out += fmt::format("reference point Px = {} mm ({})\n", SummaryNum(a.reference_position_mm, 2), a.reference_source);
    out += fmt::format("ρ = {} µm/mm/°C ({})\n", SummaryNum(a.rho_um_per_mm_per_c, 6), a.rho_source);
    if (std::isfinite(a.rho_fitted_for_check))
      out += fmt::format("  (the calibration's room changes alone would fit ρ = {} µm/mm/°C)\n", SummaryNum(a.rho_fitted_for_check, 6));
    if (std::isfinite(a.room_range_c[0]))
      out += fmt::format("room temperatures of the calibration: {}–{} °C; beyond them {}\n", SummaryNum(a.room_range_c[0], 1),
                         SummaryNum(a.room_range_c[1], 1),
                         a.rho_from_cte
                             ? "the room's soak (ρ, from the CTE) still holds; the fitted thermal terms are alarmed as extrapolated"
                             : "the model extrapolates (alarmed): measure a state in another season, or give the CTE for the soak");
    out += fmt::format("candidate sensors: {}\n",
                       a.candidate_sensors.empty() ? std::string("none") : fmt::format("{}", fmt::join(a.candidate_sensors, ", ")));
    out += fmt::format("key sensors: {}\n",
                       a.key_sensors.empty() ? std::string("none") : fmt::format("{}", fmt::join(a.key_sensors, ", ")));
    out += fmt::format("why: {}\n", a.key_selection_reason);
    for (const auto& st : a.selection_steps)
      out += fmt::format("  step [{}]: LOSO CV RMS {} µm  {}\n", fmt::join(st.keys, ", "), SummaryNum(st.cv_rms_um), st.note);
    if (!a.lag_reason.empty()) {
      out += fmt::format("key sensor lag τ = {} s: {}\n", SummaryNum(a.key_lag_s, 0), a.lag_reason);
      for (const auto& c : a.lag_candidates)
        out += fmt::format("  τ {:>6} s: LOSO CV RMS {} µm\n", SummaryNum(c[0], 0), SummaryNum(c[1]));
    }
    if (!a.key_offsets_reason.empty()) out += fmt::format("pivots: {}\n", a.key_offsets_reason);
    if (!a.motion_reason.empty()) {
      out += fmt::format("motion heat: {}\n", a.motion_reason);
      for (const auto& c : a.motion_candidates)
        out += fmt::format("  τ {:>6} s: LOSO CV RMS {} µm\n", SummaryNum(c[0], 0), SummaryNum(c[1]));
    }
    for (const auto& n : a.coolant_notes) out += "  " + n + "\n";
    for (const auto& n : a.fallback_notes) out += "  " + n + "\n";
    out += "states (µm; residual = measured − model, all points):\n";
    out += fmt::format("  {:<16} {:<8} {:<7} {:>6} {:>10} {:>10} {:>10} {:>9} {:>9} {:>11} {:>11}  mean key rises °C\n",
                       "state", "kind", "coolant", "points", "uncorr RMS", "uncorr max", "geom-only", "resid RMS",
                       "resid max", "tanβ fwd", "tanβ rev");
    for (const auto& s : a.states) {
      std::vector<std::string> rises;
      for (double r : s.mean_key_rise_c) rises.push_back(SummaryNum(r, 2));
      out += fmt::format("  {:<16} {:<8} {:<7} {:>6} {:>10} {:>10} {:>10} {:>9} {:>9} {:>11} {:>11}  {}\n", s.label,
                         StateKindName(s.kind), CoolantStateName(s.coolant), s.points, SummaryNum(s.uncorrected_rms_um),
                         SummaryNum(s.uncorrected_max_um), SummaryNum(s.geometric_only_rms_um), SummaryNum(s.residual_rms_um),
                         SummaryNum(s.residual_max_um), SummaryNum(s.tan_beta_um_per_mm[0], 5), SummaryNum(s.tan_beta_um_per_mm[1], 5),
                         fmt::join(rises, " "));
    }
    if (!a.diagnosis.states.empty()) out += ResidualDiagnosisTable(a.diagnosis) + ResidualDiagnosisBrief(a.diagnosis);
  }
  if (!warnings.empty()) out += "warnings:\n";
  for (const auto& w : warnings) out += "  " + w + "\n";
  return out;
}

nlohmann::json FitSummary::ToJson() const {
  using nlohmann::json;
  json axes_j = json::array();
  for (const auto& a : axes) {
    json dirs = json::array();
    for (const auto& d : a.directions) {
      json cands = json::array();
      for (const auto& c : d.degree.candidates)
        cands.push_back({{"degree", c.degree}, {"fit_rms_um", JsonNum(c.fit_rms_um)}, {"cv_rms_um", JsonNum(c.cv_rms_um)}});
      json dj{{"kind", KindText(d.kind)},
              {"targets", d.targets},
              {"runs", d.runs},
              {"fit_rms_um", JsonNum(d.geometric_fit_rms_um)},
              {"cv_rms_um", JsonNum(d.geometric_cv_rms_um)},
              {"table_cv_rms_um", JsonNum(d.table_cv_rms_um)}};
      dj["choice"] = d.choice;
      if (!d.degree.candidates.empty()) {
        dj["degree"] = d.degree.degree;
        dj["degree_candidates"] = cands;
        dj["noise_um"] = JsonNum(d.degree.noise_um);
        dj["degree_rule"] = d.degree.rule;
      }
      dirs.push_back(dj);
    }
    json steps = json::array();
    for (const auto& s : a.selection_steps) steps.push_back({{"keys", s.keys}, {"cv_rms_um", JsonNum(s.cv_rms_um)}, {"note", s.note}});
    json states = json::array();
    for (const auto& s : a.states) {
      json rises = json::array();
      for (double r : s.mean_key_rise_c) rises.push_back(JsonNum(r));
      states.push_back({{"label", s.label},
                        {"path", s.path},
                        {"kind", StateKindName(s.kind)},
                        {"coolant", std::string(CoolantStateName(s.coolant))},
                        {"used_for_thermal", s.used_for_thermal},
                        {"points", s.points},
                        {"mean_key_rise_c", rises},
                        {"mean_ambient_rise_c", JsonNum(s.mean_ambient_rise_c)},
                        {"tan_beta_forward_um_per_mm", JsonNum(s.tan_beta_um_per_mm[0])},
                        {"tan_beta_reverse_um_per_mm", JsonNum(s.tan_beta_um_per_mm[1])},
                        {"uncorrected_rms_um", JsonNum(s.uncorrected_rms_um)},
                        {"uncorrected_max_um", JsonNum(s.uncorrected_max_um)},
                        {"geometric_only_rms_um", JsonNum(s.geometric_only_rms_um)},
                        {"residual_rms_um", JsonNum(s.residual_rms_um)},
                        {"residual_max_um", JsonNum(s.residual_max_um)}});
    }
    axes_j.push_back({{"axis", a.axis},
                      {"cold_source", a.cold_source},
                      {"forward", dirs[0]},
                      {"reverse", dirs[1]},
                      {"thermal_fitted", a.thermal_fitted},
                      {"candidate_sensors", a.candidate_sensors},
                      {"key_sensors", a.key_sensors},
                      {"key_selection_reason", a.key_selection_reason},
                      {"selection_steps", steps},
                      {"thermal_cv_rms_um", JsonNum(a.thermal_cv_rms_um)},
                      {"key_lag_s", JsonNum(a.key_lag_s)},
                      {"lag_reason", a.lag_reason},
                      {"motion_lag_s", JsonNum(a.motion_lag_s)},
                      {"motion_reason", a.motion_reason},
                      {"motion_candidates", [&] {
                         nlohmann::json arr = nlohmann::json::array();
                         for (const auto& c : a.motion_candidates) arr.push_back({{"tau_s", JsonNum(c[0])}, {"cv_rms_um", JsonNum(c[1])}});
                         return arr;
                       }()},
                      {"key_offsets", a.key_offsets},
                      {"key_offsets_reason", a.key_offsets_reason},
                      {"lag_candidates", [&] {
                         nlohmann::json arr = nlohmann::json::array();
                         for (const auto& c : a.lag_candidates) arr.push_back({{"tau_s", JsonNum(c[0])}, {"cv_rms_um", JsonNum(c[1])}});
                         return arr;
                       }()},
                      {"no_thermal_cv_rms_um", JsonNum(a.no_thermal_cv_rms_um)},
                      {"reference_source", a.reference_source},
                      {"rho_source", a.rho_source},
                      {"rho_from_cte", a.rho_from_cte},
                      {"rho_fitted_for_check_um_per_mm_per_c", JsonNum(a.rho_fitted_for_check)},
                      {"room_range_c", {JsonNum(a.room_range_c[0]), JsonNum(a.room_range_c[1])}},
                      {"coolant_notes", a.coolant_notes},
                      {"fallback_notes", a.fallback_notes},
                      {"states", states}});
  }
  return {{"axes", axes_j}, {"warnings", warnings}};
}

}  // namespace trueaxis::model
