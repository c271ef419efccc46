#include "trueaxis/runtime/run_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <arpa/inet.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::runtime {
namespace {

std::string Resolve(const std::string& base_dir, const std::string& p) {
  if (p.empty() || std::filesystem::path(p).is_absolute() || base_dir.empty()) return p;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

}  // namespace

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

void ReadThermalChannels(TomlTableReader& m, RunConfig& c) {
  const std::string& source = m.source();
  if (const toml::table* tc = m.Table("thermal_channels")) {
    TomlTableReader t(*tc, source, m.Key("thermal_channels"));
    for (const auto& [axis, v] : *tc) {
      std::string channel;
      t.String(axis.str(), channel, true);
      c.thermal_channels[std::string(axis.str())] = channel;
    }
    if (c.thermal_channels.empty())
      m.Fail("thermal_channels", m.Node("thermal_channels"), "names no axis (e.g. thermal_channels = { Z = \"e_z\" })");
  }
}

void ReadSignalTable(TomlTableReader& r, const std::string& base, RunConfig& c) {
  const std::string& source = r.source();
  const toml::table* t = r.Table("signal");
  if (!t) return;
  TomlTableReader m(*t, source, r.Key("signal"));
  m.Bool("enabled", c.signal_processing);
  if (m.String("calibration", c.calibration_file)) c.calibration_file = Resolve(base, c.calibration_file);
  c.lines["signal.calibration"] = m.Line(t->get("calibration"));
  if (const toml::node* g = m.Node("groups")) {
    const char* form = "an array of groups of redundant channels, e.g. [[\"y_nut\", \"y_nut_b\"]]";
    const toml::array* groups = g->as_array();
    if (!groups) m.Fail("groups", g, std::string("expected ") + form);
    for (const auto& e : *groups) {
      const toml::array* group = e.as_array();
      if (!group || group->size() < 2) m.Fail("groups", &e, std::string("each group needs at least two channel names: ") + form);
      std::vector<std::string> names;
      for (const auto& n : *group) {
        const auto name = n.value<std::string>();
        if (!name) m.Fail("groups", &n, "a channel name is a string");
        if (std::find(names.begin(), names.end(), *name) != names.end()) m.Fail("groups", &n, "'" + *name + "' twice in one group");
        names.push_back(*name);
      }
      c.redundant_groups.push_back(std::move(names));
    }
    c.redundant_groups_line = m.Line(g);
  }
  m.Double("max_disagreement_c", c.compensator.sensor.judge.max_disagreement_c, 0.1, 50);
  m.RejectUnknown();
  if (!c.redundant_groups.empty() && !c.signal_processing)
    m.Fail("groups", t->get("groups"), "needs enabled = true (the signal processing compares the channels)");
  if (!c.calibration_file.empty() && !c.signal_processing)
    m.Fail("calibration", t->get("calibration"), "needs enabled = true (calibration is applied by the signal processing)");
}

RunConfig ParseRunConfig(const std::string& text, const std::string& source, bool model_required) {
  const toml::table root = ParseTomlOrThrow(text, source);
  RunConfig c;
  c.source = source;
  const std::string base = std::filesystem::path(source).parent_path().string();
  TomlTableReader r(root, source, "");

  const toml::table* mt = r.Table("machine");
  if (!mt) r.Fail("machine", nullptr, "missing (required): [machine] with kind = \"virtual\" or \"modbus\"");
  {
    TomlTableReader m(*mt, source, "machine");
    const int kind = m.Choice("kind", {"virtual", "modbus"});
    if (kind < 0) m.Fail("kind", nullptr, "missing (required): \"virtual\" or \"modbus\"");
    c.machine = kind == 0 ? MachineKind::kVirtual : MachineKind::kModbus;
    auto& v = c.virtual_machine;
    if (m.String("file", v.machine_file)) v.machine_file = Resolve(base, v.machine_file);
    m.U64("seed", v.seed);
    m.Double("time_scale", v.time_scale, 0.01, 1e6);
    m.Bool("reciprocate", v.reciprocate);
    m.Double("feed_mm_min", v.feed_mm_min, 1, 1e5);
    m.Double("duty", v.duty, 0.01, 1);
    const int coolant = m.Choice("coolant", {"off", "flood", "mist", "air"});
    if (coolant >= 0) v.coolant = static_cast<CoolantState>(coolant);
    auto& b = c.modbus;
    m.String("name", b.machine_name);
    m.String("host", b.host);
    m.Int("port", b.port, 1, 65535);
    m.Int("cnc_unit_id", b.cnc_unit_id, 0, 247);
    m.Int("first_rtd_unit_id", b.first_rtd_unit_id, 0, 247);
    m.UniqueStrings("axes", b.axis_names, "axis");
    m.UniqueStrings("channels", b.channel_names, "channel");
    m.Double("response_timeout_s", b.response_timeout_s, 0.001, 10);
    m.RejectUnknown();
    for (const char* key : {"file", "name", "host", "axes", "channels", "cnc_unit_id", "first_rtd_unit_id"})
      c.lines[std::string("machine.") + key] = m.Line(mt->get(key));
    if (c.machine == MachineKind::kVirtual && v.machine_file.empty())
      m.Fail("file", nullptr, "missing (required for kind = \"virtual\"): the machine TOML");
    if (c.machine == MachineKind::kVirtual && mt->contains("name"))
      m.Fail("name", mt->get("name"), "only for kind = \"modbus\": a virtual machine is named by its machine file");
    if (c.machine == MachineKind::kModbus) {
      if (b.axis_names.empty()) m.Fail("axes", nullptr, "must list at least one axis");
      // A dotted quad that is no IPv4 address (999.1.1.1) is a typo, not a host name to look up.
      in_addr addr{};
      if (!b.host.empty() && b.host.find_first_not_of("0123456789.") == std::string::npos &&
          inet_pton(AF_INET, b.host.c_str(), &addr) != 1)
        m.Fail("host", mt->get("host"), fmt::format("'{}' is not an IPv4 address", b.host));
    }
  }

  const toml::table* mo = r.Table("model");
  if (!mo && model_required) r.Fail("model", nullptr, "missing (required): [model] with file = \"model.json\"");
  if (mo) {
    TomlTableReader m(*mo, source, "model");
    m.String("file", c.model_file, true);
    c.model_file = Resolve(base, c.model_file);
    c.lines["model.file"] = m.Line(mo->get("file"));
    m.Bool("reload", c.model_reload);
    ReadThermalChannels(m, c);
    m.RejectUnknown();
  }

  if (const toml::table* t = r.Table("loop")) {
    TomlTableReader m(*t, source, "loop");
    m.Double("period_s", c.period_s, 1e-4, 10);
    m.Double("temperature_period_s", c.temperature_period_s, 1e-4, 60);
    m.Double("duration_s", c.duration_s, 0, 1e9);
    m.RejectUnknown();
    if (t->contains("temperature_period_s") && c.temperature_period_s < c.period_s)
      m.Fail("temperature_period_s", t->get("temperature_period_s"), "must be at least period_s");
  }
  if (c.temperature_period_s < c.period_s) c.temperature_period_s = c.period_s;  // a long period with the default

  std::vector<int> axis_lines;
  ReadCompensatorTables(r, c.period_s, c.compensator, c.axes, &axis_lines);
  for (std::size_t i = 0; i < axis_lines.size(); ++i) c.lines[fmt::format("axis[{}].name", i)] = axis_lines[i];
  auto& o = c.compensator;
  ReadSignalTable(r, base, c);
  if (const toml::table* t = r.Table("history")) {
    TomlTableReader m(*t, source, "history");
    // A path (SQLite, relative to this file) or a database URL (postgresql://…, taken as written).
    if (m.String("db", c.history_db) && c.history_db.find("://") == std::string::npos) c.history_db = Resolve(base, c.history_db);
    if (m.String("csv", c.log_csv)) c.log_csv = Resolve(base, c.log_csv);
    m.Double("record_interval_s", c.record_interval_s, 1e-4, 1e6);
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("web")) {
    TomlTableReader m(*t, source, "web");
    m.String("listen", c.web.listen);
    for (auto [key, path] : {std::pair{"users", &c.web.users}, {"cert", &c.web.cert}, {"key", &c.web.key}})
      if (m.String(key, *path)) *path = Resolve(base, *path);
    m.String("machine_id", c.web.machine_id);
    m.RejectUnknown();
    for (const char* key : {"listen", "users", "cert", "key", "machine_id"})
      if (t->contains(key)) c.lines[std::string("web.") + key] = m.Line(t->get(key));
  }
  r.RejectUnknown();
  std::string why;
  if (!o.IsValid(&why)) throw InputError(source, why);
  return c;
}

void RunConfig::RequireFile(const std::string& key, const std::string& path) const {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (st.type() == std::filesystem::file_type::not_found)
    throw InputError(source, LineOf(key), key, fmt::format("'{}' does not exist", path));
  if (st.type() == std::filesystem::file_type::directory)
    throw InputError(source, LineOf(key), key, fmt::format("'{}' is a folder, not a file", path));
}

RunConfig ReadRunConfig(const std::string& path, bool model_required) {
  return ParseRunConfig(ReadTextFile(path), path, model_required);
}

}  // namespace trueaxis::runtime
