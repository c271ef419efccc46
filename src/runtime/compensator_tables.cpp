#include "trueaxis/runtime/compensator_tables.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::runtime {

void ReadCompensatorTables(TomlTableReader& r, double period_s, CompensatorOptions& o, std::vector<AxisInterface>& axes,
                           std::vector<int>* axis_lines) {
  // A CNC snapshot is stale after 3 loop periods, at least 0.25 s, unless [link] stale_after_s says.
  o.link_stale_after_s = std::max(o.link_stale_after_s, 3 * period_s);
  if (const toml::table* t = r.Table("limits")) {
    TomlTableReader m(*t, r.source(), r.Key("limits"));
    m.Double("max_correction_um", o.shaper.max_correction_um, 1e-3, 1e5);  // 0 would hold every correction at 0
    m.Double("max_step_um", o.shaper.max_step_um, 1e-6, 1e5);
    m.Double("hysteresis", o.shaper.hysteresis, 0, 0.5);
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("sensor_fault")) {
    TomlTableReader m(*t, r.source(), r.Key("sensor_fault"));
    // The per-value limits are the temperature judge's (signal::TemperatureMonitor), under the
    // names the run config has always used; the step itself judges no value.
    signal::FaultOptions& judge = o.sensor.judge;
    m.Double("min_valid_c", judge.min_plausible_c, -273, 1000);
    m.Double("max_valid_c", judge.max_plausible_c, -273, 1000);
    m.Double("max_rate_c_per_s", judge.max_rate_c_per_s, 0, 1e3);
    m.Double("rate_allowance_c", judge.rate_allowance_c, 0, 100);
    m.Double("hold_last_good_s", o.sensor.hold_last_good_s, 0, 1e6);
    m.Double("fallback_handover_s", o.sensor.fallback_handover_s, 0, 1e6);
    m.Double("stale_after_s", o.sensor.stale_after_s, 1e-3, 1e6);
    const int fb = m.Choice("fallback", {"geometric", "zero"});
    if (fb >= 0) o.sensor.fallback = fb == 0 ? SensorFallback::kGeometricOnly : SensorFallback::kZero;
    m.RejectUnknown();
    if (!(judge.min_plausible_c < judge.max_plausible_c))
      m.Fail("max_valid_c", t->get("max_valid_c"), "must be greater than min_valid_c");
  }
  if (const toml::table* t = r.Table("link")) {
    TomlTableReader m(*t, r.source(), r.Key("link"));
    const int lp = m.Choice("loss_policy", {"hold", "ramp_to_zero"});
    if (lp >= 0) o.link_loss = lp == 0 ? LinkLossPolicy::kHold : LinkLossPolicy::kRampToZero;
    m.Int("recovery_cycles", o.link_recovery_cycles, 1, 100000);
    m.Double("stale_after_s", o.link_stale_after_s, 1e-3, 1e6);
    if (t->contains("stale_after_s") && o.link_stale_after_s < 2 * period_s)
      m.Fail("stale_after_s", t->get("stale_after_s"),
             fmt::format("must be at least twice the loop period ({} s): every CNC snapshot would be stale", period_s));
    m.Bool("follow_cnc_enable", o.follow_cnc_enable);
    m.Bool("direction_only_while_moving", o.direction_only_while_moving);
    m.Double("direction_min_move_um", o.direction_min_move_um, 1e-3, 1e4);
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("channels")) {
    TomlTableReader m(*t, r.source(), r.Key("channels"));
    for (const auto& [k, v] : *t) {
      std::string target;
      m.String(k.str(), target);
      o.channel_map[std::string(k.str())] = target;
    }
  }
  if (const toml::node* n = r.Node("axis")) {
    const toml::array* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) r.Fail("axis", n, "must be an array of tables ([[axis]])");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::table& at = *(*arr)[i].as_table();
      TomlTableReader m(at, r.source(), r.Key(fmt::format("axis[{}]", i)));
      AxisInterface a;
      m.String("name", a.axis, true);
      m.Double("pulse_equivalent_um", a.pulse_equivalent_um, 1e-6, 1e4);
      const int prog = m.Choice("programming", {"radius", "diameter"});
      if (prog >= 0) a.programming = prog == 0 ? Programming::kRadius : Programming::kDiameter;
      m.Double("position_offset_mm", a.position_offset_mm, -1e6, 1e6);
      m.Double("reference_position_mm", a.reference_position_mm, -1e6, 1e6);
      m.Bool("enabled", a.enabled);
      m.Double("max_correction_um", a.max_correction_um, 1e-3, 1e4);
      m.RejectUnknown();
      for (const auto& prev : axes)
        if (prev.axis == a.axis) m.Fail("name", at.get("name"), fmt::format("axis '{}' is configured twice", a.axis));
      axes.push_back(a);
      if (axis_lines) axis_lines->push_back(m.Line(at.get("name")));
    }
  }
}

}  // namespace trueaxis::runtime
