#include "trueaxis/station/installation_config.hpp"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/runtime/compensator_tables.hpp"

namespace trueaxis::station {

std::string ResolveConfigPath(const std::string& base_dir, const std::string& p) {
  if (p.empty() || std::filesystem::path(p).is_absolute() || base_dir.empty()) return p;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

signal::MonitorOptions TemperatureJudgeOptions(const InstallationConfig& c) {
  signal::MonitorOptions o;
  o.faults = c.compensator.sensor.judge;
  o.neighbour_groups = c.redundant_groups;
  if (!c.signal_processing) o.filter = signal::FilterOptions::PassThrough();  // judged all the same
  return o;
}

void ReadThermalChannels(TomlTableReader& m, InstallationConfig& c) {
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

void ReadSignalTable(TomlTableReader& r, const std::string& base, InstallationConfig& c) {
  const std::string& source = r.source();
  const toml::table* t = r.Table("signal");
  if (!t) return;
  TomlTableReader m(*t, source, r.Key("signal"));
  m.Bool("enabled", c.signal_processing);
  if (m.String("calibration", c.calibration_file)) c.calibration_file = ResolveConfigPath(base, c.calibration_file);
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

void ReadInstallationTables(TomlTableReader& r, InstallationConfig& c, bool model_required) {
  const std::string& source = r.source();
  c.source = source;
  const std::string base = std::filesystem::path(source).parent_path().string();
  const toml::table* mo = r.Table("model");
  if (!mo && model_required) r.Fail("model", nullptr, "missing (required): [model] with file = \"model.json\"");
  if (mo) {
    TomlTableReader m(*mo, source, "model");
    m.String("file", c.model_file, true);
    c.model_file = ResolveConfigPath(base, c.model_file);
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
  runtime::ReadCompensatorTables(r, c.period_s, c.compensator, c.axes, &axis_lines);
  for (std::size_t i = 0; i < axis_lines.size(); ++i) c.lines[fmt::format("axis[{}].name", i)] = axis_lines[i];
  ReadSignalTable(r, base, c);
}

void InstallationConfig::RequireFile(const std::string& key, const std::string& path) const {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (st.type() == std::filesystem::file_type::not_found)
    throw InputError(source, LineOf(key), key, fmt::format("'{}' does not exist", path));
  if (st.type() == std::filesystem::file_type::directory)
    throw InputError(source, LineOf(key), key, fmt::format("'{}' is a folder, not a file", path));
}

}  // namespace trueaxis::station
