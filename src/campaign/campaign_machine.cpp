#include "trueaxis/campaign/campaign_machine.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::campaign {

const std::vector<Controller>& AllControllers() {
  static const std::vector<Controller> all = {Controller::kLinuxCnc, Controller::kFanuc, Controller::kSinumerik,
                                              Controller::kHeidenhain};
  return all;
}

std::string_view ControllerName(Controller c) {
  switch (c) {
    case Controller::kLinuxCnc: return "linuxcnc";
    case Controller::kFanuc: return "fanuc";
    case Controller::kSinumerik: return "sinumerik";
    case Controller::kHeidenhain: return "heidenhain";
  }
  return "linuxcnc";
}

std::string_view ControllerTitle(Controller c) {
  switch (c) {
    case Controller::kLinuxCnc: return "LinuxCNC";
    case Controller::kFanuc: return "FANUC";
    case Controller::kSinumerik: return "SINUMERIK";
    case Controller::kHeidenhain: return "HEIDENHAIN (Klartext)";
  }
  return "LinuxCNC";
}

std::optional<Controller> ParseController(std::string_view name) {
  const std::string l = LowerAscii(name);
  for (Controller c : AllControllers())
    if (l == ControllerName(c)) return c;
  return std::nullopt;
}

int CampaignMachine::AxisIndex(std::string_view name) const {
  const std::string l = LowerAscii(name);
  for (std::size_t i = 0; i < axes.size(); ++i)
    if (LowerAscii(axes[i].name) == l) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> CampaignMachine::SensorsAt(const std::string& location) const {
  std::vector<std::string> out;
  for (const auto& s : sensors)
    if (s.location == location) out.push_back(s.name);
  return out;
}

namespace {

bool KnownLocation(const std::string& location, const std::vector<CampaignAxis>& axes) {
  for (const char* l : {"ambient", "bed", "bed_top", "bed_bottom", "coolant", "spindle"})
    if (location == l) return true;
  for (const auto& a : axes)
    for (const char* suffix : {"_nut", "_bearing", "_floating_bearing", "_motor", "_structure"})
      if (location == LowerAscii(a.name) + suffix) return true;
  return false;
}

// The nut of every axis and the room must be measured: said at the file, before a campaign starts.
void RequireKeySensors(const CampaignMachine& m, int sensor_line) {
  for (const auto& a : m.axes)
    if (m.SensorsAt(LowerAscii(a.name) + "_nut").empty())
      throw InputError(m.source, sensor_line, "sensor",
                       fmt::format("no sensor at location '{}_nut': the warm-up tests of axis {} are timed by its nut's "
                                   "rise (mount one on the nut housing, docs/real-machine.md)",
                                   LowerAscii(a.name), a.name));
  if (m.SensorsAt("ambient").empty())
    throw InputError(m.source, sensor_line, "sensor",
                     "no sensor at location 'ambient': the room's temperature is what the model's reach is judged by "
                     "(mount one in the air beside the machine, docs/real-machine.md)");
}

CampaignMachine FromVirtualMachine(const std::string& text, const std::string& source) {
  const sim::MachineDescription d = sim::ParseMachineToml(text, source);
  CampaignMachine m;
  m.source = source;
  m.name = d.name;
  m.virtual_machine_file = true;
  for (const auto& a : d.axes)
    m.axes.push_back({a.name, 0.0, a.travel_mm, a.lead_mm, a.fixed_end == sim::FixedEnd::kMin, a.reference_mm});
  for (const auto& s : d.sensors) m.sensors.push_back({s.name, s.location});
  RequireKeySensors(m, 0);
  return m;
}

}  // namespace

CampaignMachine ParseCampaignMachineToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  const toml::table* machine_table = root["machine"].as_table();
  if (!machine_table || !machine_table->contains("controller")) return FromVirtualMachine(text, source);

  CampaignMachine m;
  m.source = source;
  TomlTableReader r(root, source, "");
  if (const auto* t = r.Table("machine")) {
    TomlTableReader mr(*t, source, "machine");
    mr.String("name", m.name);
    std::string controller;
    mr.String("controller", controller, true);
    m.controller = ParseController(controller);
    if (!m.controller)
      mr.Fail("controller", mr.Node("controller"),
              fmt::format("'{}' is not linuxcnc, fanuc, sinumerik or heidenhain", controller));
    mr.RejectUnknown();
  }
  const toml::node* axes_node = r.Node("axis");
  if (!axes_node) r.Fail("axis", nullptr, "no [[axis]] defined");
  const auto* axes = axes_node->as_array();
  if (!axes || !axes->is_array_of_tables()) r.Fail("axis", axes_node, "must be an array of tables ([[axis]])");
  for (std::size_t i = 0; i < axes->size(); ++i) {
    const toml::table& at = *(*axes)[i].as_table();
    TomlTableReader ar(at, source, fmt::format("axis[{}]", i));
    CampaignAxis a;
    ar.String("name", a.name, true);
    for (auto& c : a.name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (a.name.empty() || a.name.size() > 3 ||
        !std::all_of(a.name.begin(), a.name.end(), [](char c) { return c >= 'A' && c <= 'Z'; }))
      ar.Fail("name", at.get("name"), "must be 1–3 letters (X, Y, Z, …)");
    if (m.AxisIndex(a.name) >= 0) ar.Fail("name", at.get("name"), fmt::format("axis '{}' is defined twice", a.name));
    double travel = std::nan("");
    ar.Double("travel_mm", travel, 1, 100000);
    const bool has_limits = at.contains("min_mm") || at.contains("max_mm");
    if (has_limits && std::isfinite(travel))
      ar.Fail("travel_mm", at.get("travel_mm"), "give either travel_mm (the axis from 0) or min_mm and max_mm, not both");
    if (has_limits) {
      ar.Double("min_mm", a.min_mm, -100000, 100000, true);
      ar.Double("max_mm", a.max_mm, -100000, 100000, true);
      if (!(a.max_mm - a.min_mm >= 1))
        ar.Fail("max_mm", at.get("max_mm"), fmt::format("{} mm is not at least 1 mm above min_mm {} mm", a.max_mm, a.min_mm));
    } else {
      if (!std::isfinite(travel)) ar.Fail("travel_mm", nullptr, "missing: give travel_mm, or min_mm and max_mm (soft limits)");
      a.min_mm = 0;
      a.max_mm = travel;
    }
    ar.Double("lead_mm", a.lead_mm, 0.5, 200, true);
    const int fixed = ar.Choice("fixed_end", {"min", "max"});
    a.fixed_at_min = fixed != 1;
    a.reference_mm = a.fixed_at_min ? a.min_mm : a.max_mm;
    ar.Double("reference_mm", a.reference_mm, a.min_mm, a.max_mm);
    ar.Double("cte_um_per_m_c", a.cte_um_per_m_c, -30, 30);
    ar.RejectUnknown();
    m.axes.push_back(a);
  }
  int sensor_line = 0;
  if (const toml::node* n = r.Node("sensor")) {
    const auto* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) r.Fail("sensor", n, "must be an array of tables ([[sensor]])");
    sensor_line = r.Line(n);
    std::set<std::string> names;
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::table& st = *(*arr)[i].as_table();
      TomlTableReader sr(st, source, fmt::format("sensor[{}]", i));
      CampaignSensor s;
      sr.String("name", s.name, true);
      if (!sim::ValidSensorName(s.name)) sr.Fail("name", st.get("name"), "must be lower case letters, digits and '_' (e.g. x_nut)");
      if (!names.insert(s.name).second) sr.Fail("name", st.get("name"), fmt::format("sensor '{}' is defined twice", s.name));
      s.location = s.name;
      sr.String("location", s.location);
      if (!KnownLocation(s.location, m.axes))
        sr.Fail("location", st.get("location") ? st.get("location") : st.get("name"),
                fmt::format("unknown location '{}' (use <axis>_nut, <axis>_bearing, <axis>_floating_bearing, "
                            "<axis>_motor, <axis>_structure, bed, bed_top, bed_bottom, ambient, coolant, spindle)",
                            s.location));
      sr.RejectUnknown();
      m.sensors.push_back(s);
    }
  } else {
    r.Fail("sensor", nullptr, "no [[sensor]] defined: list the sensors you mounted (name and location)");
  }
  r.RejectUnknown();
  RequireKeySensors(m, sensor_line);
  return m;
}

CampaignMachine ReadCampaignMachineFile(const std::string& path) {
  return ParseCampaignMachineToml(ReadTextFile(path), path);
}

}  // namespace trueaxis::campaign
