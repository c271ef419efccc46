#include "trueaxis/terminal/terminal_config.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::terminal {
namespace {

std::string Resolve(const std::string& base_dir, const std::string& p) {
  if (p.empty() || std::filesystem::path(p).is_absolute() || base_dir.empty()) return p;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

// The tables of an array of tables `key` ([[key]]); empty when absent.
std::vector<const toml::table*> TablesOf(TomlTableReader& r, std::string_view key) {
  std::vector<const toml::table*> out;
  const toml::node* n = r.Node(key);
  if (!n) return out;
  const toml::array* arr = n->as_array();
  if (!arr || !arr->is_array_of_tables()) r.Fail(key, n, fmt::format("must be an array of tables ([[{}]])", r.Key(key)));
  for (const auto& e : *arr) out.push_back(e.as_table());
  return out;
}

void ReadPoll(TomlTableReader& m, PollSettings& poll, const toml::table& t) {
  m.Double("poll_period_s", poll.period_s, 1e-3, 3600);
  m.Double("stale_after_s", poll.stale_after_s, 1e-3, 36000);
  if (!(poll.stale_after_s > poll.period_s))
    m.Fail("stale_after_s", t.get("stale_after_s"),
           fmt::format("must be longer than poll_period_s ({} s): every reading would count as stale", poll.period_s));
}

}  // namespace

std::vector<std::string> TerminalConfig::ChannelNames() const {
  std::vector<std::string> names;
  if (one_wire.present)
    for (const auto& s : one_wire.options.sensors) names.push_back(s.channel);
  for (const auto& g : rtd) names.insert(names.end(), g.options.channel_names.begin(), g.options.channel_names.end());
  return names;
}

TerminalConfig ParseTerminalConfig(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  TerminalConfig c;
  c.source = source;
  c.server.bind_address = "127.0.0.1";
  c.server.watchdog_s = 2.0;  // a terminal in a shop fails safe by default
  const std::string base = std::filesystem::path(source).parent_path().string();
  TomlTableReader r(root, source, "");

  if (const toml::table* t = r.Table("serve")) {
    TomlTableReader m(*t, source, "serve");
    auto& s = c.server;
    m.String("bind", s.bind_address);
    m.Int("port", s.port, 1, 65535);
    m.Int("pmc_unit_id", s.pmc_unit_id, 0, 247);
    m.Int("first_rtd_unit_id", s.first_rtd_unit_id, 0, 247);
    m.Double("machine_period_s", s.machine_period_s, 1e-3, 10);
    m.Double("max_compensation_um", s.max_abs_compensation_um, 1e-3, 1e5);
    m.Double("watchdog_s", s.watchdog_s, 0, 3600);
    m.Double("watchdog_ramp_um_per_s", s.watchdog_ramp_um_per_s, 1e-3, 1e5);
    m.Int("max_clients", s.max_clients, 1, 1000);
    m.RejectUnknown();
  }

  if (const toml::table* t = r.Table("one_wire")) {
    TomlTableReader m(*t, source, "one_wire");
    auto& w = c.one_wire;
    w.present = true;
    if (m.String("root", w.options.root)) w.options.root = Resolve(base, w.options.root);
    ReadPoll(m, w.poll, *t);
    const auto sensors = TablesOf(m, "sensor");
    if (sensors.empty()) m.Fail("sensor", nullptr, "missing: list each DS18B20 as [[one_wire.sensor]] id = \"28-…\", channel = \"…\"");
    for (std::size_t i = 0; i < sensors.size(); ++i) {
      TomlTableReader sm(*sensors[i], source, fmt::format("one_wire.sensor[{}]", i));
      OneWireSensor s;
      sm.String("id", s.id, true);
      sm.String("channel", s.channel, true);
      sm.RejectUnknown();
      if (s.id.rfind("28-", 0) != 0 || s.id.size() != 15)
        sm.Fail("id", sensors[i]->get("id"), fmt::format("'{}' is not a DS18B20 id (28-xxxxxxxxxxxx, as in {})", s.id, w.options.root));
      w.options.sensors.push_back(s);
    }
    std::string why;
    if (!w.options.IsValid(&why)) m.Fail("sensor", t->get("sensor"), why);
    // One pass converts the sensors one after the other (~0.75 s each at 12 bits): unless the
    // file says otherwise, a pass may take that long before the channels count as stale.
    if (!t->contains("stale_after_s"))
      w.poll.stale_after_s = std::max(w.poll.stale_after_s, kDs18b20ConversionS * 2.0 * static_cast<double>(w.options.sensors.size()) +
                                                               2.0 * w.poll.period_s);
  }

  for (const toml::table* t : TablesOf(r, "rtd")) {
    const std::size_t i = c.rtd.size();
    TomlTableReader m(*t, source, fmt::format("rtd[{}]", i));
    RtdSection g;
    auto& e = g.options.endpoint;
    m.String("host", e.host, true);
    m.Int("port", e.port, 1, 65535);
    m.Double("response_timeout_s", e.response_timeout_s, 1e-3, 10);
    std::vector<double> ids;
    m.Doubles("unit_ids", ids, 0, 247);
    if (!ids.empty()) {
      g.options.unit_ids.clear();
      for (double id : ids) g.options.unit_ids.push_back(static_cast<int>(id));
    }
    m.UniqueStrings("channels", g.options.channel_names, "channel");
    ReadPoll(m, g.poll, *t);
    m.RejectUnknown();
    std::string why;
    if (!g.options.IsValid(&why)) m.Fail("channels", t->get("channels"), why);
    c.rtd.push_back(std::move(g));
  }

  if (const toml::table* t = r.Table("cnc")) {
    TomlTableReader m(*t, source, "cnc");
    const int kind = m.Choice("kind", {"none", "modbus"});
    if (kind < 0) m.Fail("kind", nullptr, "missing (required): \"none\" or \"modbus\"");
    c.cnc = kind == 0 ? CncKind::kNone : CncKind::kModbus;
    auto& l = c.cnc_link;
    m.String("host", l.endpoint.host);
    m.Int("port", l.endpoint.port, 1, 65535);
    m.Double("response_timeout_s", l.endpoint.response_timeout_s, 1e-3, 10);
    m.Int("unit_id", l.unit_id, 0, 247);
    m.UniqueStrings("axes", l.axis_names, "axis");
    m.Double("stale_after_s", l.stale_after_s, 1e-3, 3600);
    m.RejectUnknown();
    if (c.cnc == CncKind::kModbus && !t->contains("host"))
      m.Fail("host", nullptr, "missing (required for kind = \"modbus\"): the CNC gateway's address");
    std::string why;
    if (c.cnc == CncKind::kModbus && !l.IsValid(&why)) m.Fail("axes", t->get("axes"), why);
  } else {
    r.Fail("cnc", nullptr, "missing (required): [cnc] kind = \"none\" (temperatures only) or \"modbus\" (a CNC gateway)");
  }
  r.RejectUnknown();

  const auto names = c.ChannelNames();
  if (names.empty()) r.Fail("one_wire", nullptr, "no temperature channel: add [one_wire] sensors or an [[rtd]] group");
  std::set<std::string> seen;
  for (const auto& n : names)
    if (!seen.insert(n).second) r.Fail("channels", nullptr, fmt::format("channel '{}' is named twice", n));
  std::string why;
  if (!c.server.IsValid(&why)) r.Fail("serve", nullptr, why);
  return c;
}

TerminalConfig ReadTerminalConfig(const std::string& path) { return ParseTerminalConfig(ReadTextFile(path), path); }

}  // namespace trueaxis::terminal
