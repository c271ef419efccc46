#include "trueaxis/server/shop_config.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/store/open_history_sink.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/drivers/pmc_window_map.hpp"
#include "trueaxis/runtime/compensator_tables.hpp"

namespace trueaxis::server {
namespace {

using station::ResolveConfigPath;

bool ValidName(const std::string& n) {
  if (n.empty() || n.size() > 31) return false;
  return std::all_of(n.begin(), n.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  });
}

}  // namespace

ShopConfig ParseShopConfig(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  ShopConfig c;
  c.source = source;
  const std::string base = std::filesystem::path(source).parent_path().string();
  TomlTableReader r(root, source, "");
  // A PostgreSQL URL is kept as written; a file name resolves against the shop file's folder.
  if (r.String("history", c.history) && !store::IsPostgresUrl(c.history)) c.history = ResolveConfigPath(base, c.history);
  if (r.String("audit_log", c.audit_log)) {
    c.audit_log = ResolveConfigPath(base, c.audit_log);
    c.audit_log_line = r.Line(r.Node("audit_log"));
  }
  if (c.audit_log.empty() && !c.history.empty()) {
    if (store::IsPostgresUrl(c.history))
      throw InputError(source, 0, "audit_log", "required when the history is a PostgreSQL URL (a file for the model-change audit log)");
    c.audit_log = c.history + ".audit.jsonl";
  }
  r.Double("record_interval_s", c.record_interval_s, 1e-3, 3600);
  if (const toml::table* t = r.Table("http")) {
    TomlTableReader m(*t, source, "http");
    m.String("bind", c.http_bind);
    m.Int("port", c.http_port, 0, 65535);
    c.http_bind_line = m.Line(m.Node("bind"));
    c.http_port_line = m.Line(m.Node("port"));
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("server")) {
    TomlTableReader m(*t, source, "server");
    m.Int("poll_threads", c.poll_threads, 1, kMaxPollThreads);
    c.poll_threads_line = m.Line(m.Node("poll_threads"));
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("mqtt")) {
    TomlTableReader m(*t, source, "mqtt");
    if (!m.String("broker", c.mqtt.broker) || c.mqtt.broker.rfind("tcp://", 0) != 0)
      m.Fail("broker", m.Node("broker"), "required: the broker as tcp://HOST:PORT (e.g. tcp://127.0.0.1:1883)");
    m.String("shop", c.mqtt.shop);
    m.String("topic_root", c.mqtt.topic_root);
    m.String("client_id", c.mqtt.client_id);
    m.Int("qos", c.mqtt.qos, 0, 2);
    m.Double("period_s", c.mqtt.period_s, 0.05, 3600);
    m.RejectUnknown();
  }
  // Shop-wide defaults of the compensator ([limits], [sensor_fault], [link], [channels]); a machine's own tables
  // override them key by key. [[axis]] is per machine only.
  runtime::CompensatorOptions defaults;
  std::vector<runtime::AxisInterface> no_axes;
  ReadCompensatorTables(r, 0.0, defaults, no_axes);
  if (!no_axes.empty()) r.Fail("axis", r.Node("axis"), "[[axis]] belongs inside a [[machine]] ([[machine.axis]])");

  const toml::node* mn = r.Node("machine");
  if (!mn) r.Fail("machine", nullptr, "missing (required): at least one [[machine]]");
  const toml::array* arr = mn->as_array();
  if (!arr || !arr->is_array_of_tables()) r.Fail("machine", mn, "must be an array of tables ([[machine]])");
  std::set<std::string> names;
  std::map<std::string, std::string> endpoints;  // host:port → the machine polling it
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table& t = *(*arr)[i].as_table();
    TomlTableReader m(t, source, fmt::format("machine[{}]", i));
    MachineConfig mc;
    mc.line = m.Line(&t);
    m.String("name", mc.name, true);
    if (!ValidName(mc.name))
      m.Fail("name", t.get("name"), "must be 1–31 characters of A–Z a–z 0–9 _ - . (it prefixes the history names)");
    if (!names.insert(mc.name).second) m.Fail("name", t.get("name"), fmt::format("machine '{}' is listed twice", mc.name));
    m.String("host", mc.host);
    in_addr addr{};
    if (inet_pton(AF_INET, mc.host.c_str(), &addr) != 1) m.Fail("host", t.get("host"), "must be an IPv4 address");
    m.Int("port", mc.port, 1, 65535);
    // Two compensators writing to one CNC would fight over its compensation registers.
    if (const auto [it, added] = endpoints.emplace(fmt::format("{}:{}", mc.host, mc.port), mc.name); !added)
      m.Fail("port", t.get("port") ? t.get("port") : t.get("host"),
             fmt::format("terminal {} is already machine '{}': two machines cannot share one terminal", it->first, it->second));
    m.Int("pmc_unit_id", mc.pmc_unit_id, 0, 255);
    m.Int("first_rtd_unit_id", mc.first_rtd_unit_id, 0, 255);
    m.UniqueStrings("axes", mc.axes, "axis");
    if (mc.axes.empty() || mc.axes.size() > drivers::pmc::kMaxAxes)
      m.Fail("axes", t.get("axes"), fmt::format("must list 1..{} axes (the PMC window's order)", drivers::pmc::kMaxAxes));
    // One name for two inputs would mix two sensors in the history and the model's reading.
    m.UniqueStrings("rtd_channels", mc.channels, "channel");
    if (m.String("model", mc.model_file, true)) mc.model_file = ResolveConfigPath(base, mc.model_file);
    m.Double("period_s", mc.period_s, 1e-3, 60);
    m.Double("temperature_period_s", mc.temperature_period_s, 1e-3, 600);
    if (t.get("temperature_period_s") && mc.temperature_period_s < mc.period_s)
      m.Fail("temperature_period_s", t.get("temperature_period_s"),
             fmt::format("must be at least period_s ({} s): the temperatures are read within a poll cycle", mc.period_s));
    if (mc.temperature_period_s < mc.period_s) mc.temperature_period_s = mc.period_s;  // the default, below a slow poll
    m.Double("response_timeout_s", mc.response_timeout_s, 1e-3, 10);
    m.Double("connect_timeout_s", mc.connect_timeout_s, 1e-3, 30);
    m.Double("min_backoff_s", mc.min_backoff_s, 1e-3, 60);
    m.Double("max_backoff_s", mc.max_backoff_s, 1e-3, 3600);
    if (mc.max_backoff_s < mc.min_backoff_s) m.Fail("max_backoff_s", t.get("max_backoff_s"), "must be at least min_backoff_s");
    std::vector<runtime::AxisInterface> axes;
    station::InstallationConfig& run = mc.installation;
    run.compensator = defaults;  // the shop's, overridden key by key
    runtime::ReadCompensatorTables(m, mc.period_s, run.compensator, axes);
    // The machine's temperature pipeline and data-driven thermal models, as `run` reads them.
    station::ReadThermalChannels(m, run);
    station::ReadSignalTable(m, base, run);
    m.RejectUnknown();
    for (const auto& name : mc.axes) {
      runtime::AxisInterface a;
      a.axis = name;
      for (const auto& given : axes)
        if (given.axis == name) a = given;
      mc.axis_interfaces.push_back(a);
    }
    for (const auto& given : axes)
      if (std::find(mc.axes.begin(), mc.axes.end(), given.axis) == mc.axes.end())
        m.Fail("axis", t.get("axis"), fmt::format("axis '{}' is not one of the machine's axes", given.axis));
    std::string why;
    if (!run.compensator.IsValid(&why)) throw InputError(source, mc.line, m.Key("limits"), why);
    run.source = source;
    run.model_file = mc.model_file;
    run.lines["model.file"] = m.Line(t.get("model"));
    run.period_s = mc.period_s;
    run.temperature_period_s = mc.temperature_period_s;
    run.axes = mc.axis_interfaces;
    c.machines.push_back(std::move(mc));
  }
  r.RejectUnknown();
  return c;
}

ShopConfig ReadShopConfig(const std::string& path) { return ParseShopConfig(ReadTextFile(path), path); }

}  // namespace trueaxis::server
