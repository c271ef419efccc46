// A flagged stand-in model for a tool with too little training, from the other tools.
#include "trueaxis/tooltherm/tool_fallback.hpp"

#include <vector>

#include "trueaxis/core/median.hpp"

namespace trueaxis::tooltherm {
double GaugeGrowthUmPerC(const ToolDescription& tool) {
  const ToolMaterial* body = FindToolMaterial(tool.material);
  const ToolMaterial* holder = FindToolMaterial(tool.holder_material);
  if (!body || !holder) return 0;
  return 1e3 * (body->expansion_per_k * tool.length_mm + holder->expansion_per_k * tool.holder_length_mm);
}

bool FallbackModelFromOtherTools(const ToolDescription& tool, const std::map<int, ToolErrorModel>& fitted,
                                 const ToolTable& table, int training_rows, ToolErrorModel* out) {
  const double growth = GaugeGrowthUmPerC(tool);
  if (!(growth > 0)) return false;
  std::vector<double> slope_per_growth, intercept, zone_slope_per_growth, zone_intercept, lag_tau;
  std::vector<int> from;
  for (const auto& [number, m] : fitted) {
    const ToolDescription* other = table.Find(number);
    if (!other || !m.fallback_from_tools.empty()) continue;  // only tools fitted on their own data
    const double g = GaugeGrowthUmPerC(*other);
    if (!(g > 0)) continue;
    slope_per_growth.push_back(m.one.per_c_um / g);
    intercept.push_back(m.one.intercept_um);
    if (!m.zone_um_per_c.empty()) {
      double zone_slope = 0;
      for (double b : m.zone_um_per_c) zone_slope += b;
      zone_slope_per_growth.push_back(zone_slope / g);
      zone_intercept.push_back(m.zone_intercept_um);
    }
    lag_tau.push_back(m.lag_tau_s);
    from.push_back(number);
  }
  if (from.empty()) return false;
  ToolErrorModel m;
  m.tool = tool.number;
  m.standard_temp_c = table.standard_temp_c;
  m.one = {Median(intercept), Median(slope_per_growth) * growth};
  m.lag_tau_s = Median(lag_tau);
  m.lag = m.one;
  m.two_body_intercept_um = m.one.intercept_um;
  m.two_body_tv_um_per_c = m.one.per_c_um;
  m.best = m.best_without_zones = ToolModelKind::kOne;
  // With zone means the stand-in is the zones model of the others scaled the same way: their
  // whole zone slope per µm of free growth (a Tv line's slope is not that: Tv underweights a thin
  // hot tip), spread over this tool's zones by each zone's free growth (ZoneGrowthUmPerC), and the
  // median of their zones intercepts (the error with every zone at the standard temperature).
  const std::vector<double> zone_growth = ZoneGrowthUmPerC(tool);
  if (!zone_growth.empty() && !zone_slope_per_growth.empty()) {
    m.zone_intercept_um = Median(zone_intercept);
    for (double g : zone_growth) m.zone_um_per_c.push_back(Median(zone_slope_per_growth) * g);
    m.best = ToolModelKind::kZones;
  }
  m.training_rows = training_rows;
  m.fallback_from_tools = from;
  *out = m;
  return true;
}

}  // namespace trueaxis::tooltherm
