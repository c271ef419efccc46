#include "trueaxis/analysis/evaluation_json.hpp"

namespace trueaxis::analysis {

nlohmann::json AxisResultToJson(const AxisResult& a) {
  return {
      {"A_um", a.A_um},         {"A_up_um", a.A_up_um},       {"A_down_um", a.A_down_um},
      {"B_um", a.B_um},         {"B_mean_um", a.B_mean_um},   {"E_um", a.E_um},
      {"E_up_um", a.E_up_um},   {"E_down_um", a.E_down_um},   {"M_um", a.M_um},
      {"R_um", a.R_um},         {"R_up_um", a.R_up_um},       {"R_down_um", a.R_down_um},
      {"P_um", a.P_um},         {"Pa_um", a.Pa_um},           {"Ps_max_um", a.Ps_max_um},
      {"Ps_mean_um", a.Ps_mean_um}, {"U_max_um", a.U_max_um}, {"U_mean_um", a.U_mean_um},
  };
}

nlohmann::json EvaluationToJson(const Evaluation& ev) {
  nlohmann::json j = AxisResultToJson(ev.axis);
  j["standard"] = ev.standard.name;
  if (!ev.standard.requested_as.empty()) j["standard_requested"] = ev.standard.requested_as;
  j["coverage_factor"] = ev.standard.coverage_factor;
  j["positions"] = ev.targets.size();
  j["runs"] = ev.runs;
  j["source"] = ev.source;
  auto& per = j["per_target"] = nlohmann::json::array();
  for (const auto& t : ev.targets) {
    per.push_back({{"target_mm", t.target_mm},
                   {"n_up", t.n_up},
                   {"n_down", t.n_down},
                   {"mean_up_um", t.mean_up_um},
                   {"mean_down_um", t.mean_down_um},
                   {"mean_um", t.mean_um},
                   {"s_up_um", t.s_up_um},
                   {"s_down_um", t.s_down_um},
                   {"B_um", t.reversal_um},
                   {"R_up_um", t.R_up_um},
                   {"R_down_um", t.R_down_um},
                   {"R_um", t.R_um},
                   {"Ps_um", t.vdi_scatter_um},
                   {"U_um", t.vdi_reversal_span_um}});
  }
  return j;
}

nlohmann::json DecompositionToJson(const Decomposition& d) {
  nlohmann::json j;
  j["lead_mm"] = d.options.lead_mm;
  j["trend_degree"] = static_cast<int>(d.trend_coefficients.size()) - 1;
  j["trend_origin_mm"] = d.trend_origin_mm;
  // Coefficients of (x − origin)^k, in µm/mm^k.
  j["trend_coefficients_um_per_mm_pow"] = d.trend_coefficients;
  j["sigma_um"] = d.sigma_um;
  j["band_sigmas"] = d.options.band_sigmas;
  j["band_half_width_um"] = d.options.band_sigmas * d.sigma_um;
  j["residual_rms_um"] = d.residual_rms_um;
  j["periodic_fitted"] = d.periodic_fitted();
  j["target_gap_min_mm"] = d.min_gap_mm;
  j["target_gap_max_mm"] = d.max_gap_mm;
  auto& hs = j["harmonics"] = nlohmann::json::array();
  for (const auto& h : d.harmonics) {
    nlohmann::json hj = {{"order", h.order}, {"period_mm", h.period_mm}, {"resolved", h.resolved}};
    if (h.resolved) {
      hj["amplitude_um"] = h.amplitude_um;
      hj["phase_rad"] = h.phase_rad;
    } else {
      hj["note"] = h.note;
    }
    hs.push_back(hj);
  }
  auto& pts = j["per_target"] = nlohmann::json::array();
  for (const auto& p : d.points)
    pts.push_back({{"target_mm", p.target_mm},
                   {"mean_um", p.mean_um},
                   {"progressive_um", p.progressive_um},
                   {"periodic_um", p.periodic_um},
                   {"residual_um", p.residual_um}});
  j["notes"] = d.notes;
  return j;
}

nlohmann::json ComparisonToJson(const Evaluation& before, const Evaluation& after) {
  const auto b = AxisResultToJson(before.axis);
  const auto a = AxisResultToJson(after.axis);
  nlohmann::json change;
  for (auto it = a.begin(); it != a.end(); ++it) change[it.key()] = it.value().get<double>() - b[it.key()].get<double>();
  nlohmann::json j = EvaluationToJson(after);
  return {{"after", j}, {"change_um", change}};
}

}  // namespace trueaxis::analysis
