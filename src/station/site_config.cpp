#include "trueaxis/station/site_config.hpp"

#include <filesystem>

#include <arpa/inet.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::station {

SiteConfig ParseSiteConfig(const std::string& text, const std::string& source, bool model_required) {
  const toml::table root = ParseTomlOrThrow(text, source);
  SiteConfig c;
  c.installation.source = source;
  auto& lines = c.installation.lines;
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
    if (m.String("file", v.machine_file)) v.machine_file = ResolveConfigPath(base, v.machine_file);
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
      lines[std::string("machine.") + key] = m.Line(mt->get(key));
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
        m.Fail("host", mt->get("host"), "'" + b.host + "' is not an IPv4 address");
    }
  }

  ReadInstallationTables(r, c.installation, model_required);  // [model], [loop], the compensator's, [signal]

  if (const toml::table* t = r.Table("history")) {
    TomlTableReader m(*t, source, "history");
    auto& h = c.history;
    // A path (SQLite, relative to this file) or a database URL (postgresql://…, taken as written).
    if (m.String("db", h.db) && h.db.find("://") == std::string::npos) h.db = ResolveConfigPath(base, h.db);
    if (m.String("csv", h.csv)) h.csv = ResolveConfigPath(base, h.csv);
    m.Double("record_interval_s", h.record_interval_s, 1e-4, 1e6);
    m.RejectUnknown();
  }
  if (const toml::table* t = r.Table("web")) {
    TomlTableReader m(*t, source, "web");
    m.String("listen", c.web.listen);
    for (auto [key, path] : {std::pair{"users", &c.web.users}, {"cert", &c.web.cert}, {"key", &c.web.key}})
      if (m.String(key, *path)) *path = ResolveConfigPath(base, *path);
    m.String("machine_id", c.web.machine_id);
    m.RejectUnknown();
    for (const char* key : {"listen", "users", "cert", "key", "machine_id"})
      if (t->contains(key)) lines[std::string("web.") + key] = m.Line(t->get(key));
  }
  r.RejectUnknown();
  std::string why;
  if (!c.installation.compensator.IsValid(&why)) throw InputError(source, why);
  return c;
}

SiteConfig ReadSiteConfig(const std::string& path, bool model_required) {
  return ParseSiteConfig(ReadTextFile(path), path, model_required);
}

}  // namespace trueaxis::station
