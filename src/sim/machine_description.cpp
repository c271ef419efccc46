// Machine file reader (docs/machine-file.md). Every value is checked for type
// and range; unknown keys are errors, because a typo silently falling back to
// a default would make a wrong machine that looks right.
#include "trueaxis/sim/machine_description.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/sim/ambient_profile.hpp"
#include "trueaxis/sim/virtual_sensor.hpp"

namespace trueaxis::sim {

int MachineDescription::AxisIndex(const std::string& name) const {
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const auto& a = axes[i].name;
    if (a.size() == name.size() &&
        std::equal(a.begin(), a.end(), name.begin(), [](char x, char y) { return std::toupper(x) == std::toupper(y); }))
      return static_cast<int>(i);
  }
  return -1;
}

std::string_view SensorKindName(SensorKind k) {
  switch (k) {
    case SensorKind::kPt100Adc: return "pt100_adc";
    case SensorKind::kDs18b20: return "ds18b20";
    case SensorKind::kRtdModule: return "rtd_module";
  }
  return "?";
}

namespace {


constexpr double kBig = 1e12;

void ReadThermal(TomlTableReader& r, DriveThermalDescription& t) {
  r.Double("reference_feed_mm_min", t.reference_feed_mm_min, 1, 1e6);
  r.Double("heat_speed_exponent", t.heat_speed_exponent, 0.3, 3);
  r.Double("nut_heat_w", t.nut_heat_w, 0, 1e4);
  r.Double("fixed_bearing_heat_w", t.fixed_bearing_heat_w, 0, 1e4);
  r.Double("floating_bearing_heat_w", t.floating_bearing_heat_w, 0, 1e4);
  r.Double("motor_heat_w", t.motor_heat_w, 0, 1e4);
  r.Double("motor_idle_heat_w", t.motor_idle_heat_w, 0, 1e4);
  r.Double("screw_convection_w_per_m2_k", t.screw_convection_w_per_m2_k, 0, 1e4);
  r.Double("screw_convection_rotating_w_per_m2_k", t.screw_convection_rotating_w_per_m2_k, 0, 1e4);
  r.Double("nut_capacity_j_per_k", t.nut_capacity_j_per_k, 1, kBig);
  r.Double("nut_to_screw_w_per_k", t.nut_to_screw_w_per_k, 0, 1e4);
  r.Double("nut_to_ambient_w_per_k", t.nut_to_ambient_w_per_k, 0, 1e4);
  r.Double("bearing_capacity_j_per_k", t.bearing_capacity_j_per_k, 1, kBig);
  r.Double("bearing_to_screw_w_per_k", t.bearing_to_screw_w_per_k, 0, 1e4);
  r.Double("bearing_to_bed_w_per_k", t.bearing_to_bed_w_per_k, 0, 1e4);
  r.Double("bearing_to_ambient_w_per_k", t.bearing_to_ambient_w_per_k, 0, 1e4);
  r.Double("motor_capacity_j_per_k", t.motor_capacity_j_per_k, 1, kBig);
  r.Double("motor_to_ambient_w_per_k", t.motor_to_ambient_w_per_k, 0, 1e4);
  r.Double("motor_to_bearing_w_per_k", t.motor_to_bearing_w_per_k, 0, 1e4);
  r.Int("screw_segments", t.screw_segments, 4, 400);
  r.Double("nut_length_mm", t.nut_length_mm, 0, 1000);
  r.RejectUnknown();
}

void ReadPitch(TomlTableReader& r, PitchErrorDescription& p) {
  r.Double("progressive_um", p.progressive_um, -1e4, 1e4);
  r.Double("curvature_um", p.curvature_um, -1e4, 1e4);
  r.Doubles("lead_harmonics_um", p.lead_harmonics_um, 0, 1e3);
  r.Double("random_um", p.random_um, 0, 1e3);
  r.Double("random_wavelength_mm", p.random_wavelength_mm, 1, 1e5);
  r.Double("flank_difference_um", p.flank_difference_um, 0, 1e3);
  r.RejectUnknown();
}

}  // namespace

bool ValidSensorName(const std::string& s) {
  if (s.empty() || s.size() > 40) return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_')) return false;
  return std::islower(static_cast<unsigned char>(s[0]));
}

MachineDescription ParseMachineToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  std::vector<std::string> declared_axes;  // [machine] axes, when given
  int declared_axes_line = 0;
  MachineDescription m;
  m.source = source;
  // Coolant defaults: flood washes the nut and screw; mist cools by evaporation
  // a little below ambient; air blast only adds convection.
  m.coolant[static_cast<int>(CoolantState::kFlood)] = {4.0, 60.0, 1.5};
  m.coolant[static_cast<int>(CoolantState::kMist)] = {1.5, 20.0, -0.5};
  m.coolant[static_cast<int>(CoolantState::kAir)] = {0.6, 10.0, 0.0};

  TomlTableReader r(root, source, "");
  if (auto* t = r.Table("machine")) {
    TomlTableReader mr(*t, source, "machine");
    mr.String("name", m.name);
    mr.Strings("axes", declared_axes);
    declared_axes_line = mr.Line(mr.Node("axes"));
    mr.U64("serial_seed", m.serial_seed);
    if (const toml::node* n = mr.Node("start")) {
      std::string iso;
      if (auto s = n->as_string()) iso = s->get();
      else if (auto dt = n->as_date_time()) {
        const auto& v = dt->get();
        iso = fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", v.date.year, v.date.month, v.date.day, v.time.hour,
                          v.time.minute, v.time.second);
      } else mr.Fail("start", n, "must be a date-time such as 2026-03-02T07:00:00");
      try {
        ParseIsoTime(iso);
      } catch (const std::exception&) {
        mr.Fail("start", n, "must be a date-time such as 2026-03-02T07:00:00");
      }
      m.start_iso = iso;
    }
    mr.Double("thermal_step_s", m.thermal_step_s, 0.01, 60);
    mr.RejectUnknown();
  }
  if (auto* t = r.Table("ambient")) {
    TomlTableReader ar(*t, source, "ambient");
    auto& a = m.ambient;
    ar.Double("mean_c", a.mean_c, -20, 50);
    ar.Double("seasonal_amplitude_c", a.seasonal_amplitude_c, 0, 30);
    ar.Double("seasonal_peak_day", a.seasonal_peak_day, 0, 366);
    ar.Double("daily_amplitude_c", a.daily_amplitude_c, 0, 20);
    ar.Double("daily_peak_hour", a.daily_peak_hour, 0, 24);
    ar.Double("weather_amplitude_c", a.weather_amplitude_c, 0, 20);
    ar.RejectUnknown();
  }
  if (auto* t = r.Table("bed")) {
    TomlTableReader br(*t, source, "bed");
    br.Double("capacity_j_per_k", m.bed.capacity_j_per_k, 1, kBig);
    br.Double("to_ambient_w_per_k", m.bed.to_ambient_w_per_k, 0.01, 1e6);
    br.Double("cte_um_per_m_c", m.bed.cte_um_per_m_c, 0, 100);
    br.RejectUnknown();
  }
  if (auto* t = r.Table("coolant")) {
    TomlTableReader cr(*t, source, "coolant");
    for (int s = 1; s < kCoolantStateCount; ++s) {
      std::string name(kCoolantStateNames[s]);
      if (auto* ct = cr.Table(name)) {
        TomlTableReader sr(*ct, source, "coolant." + name);
        auto& c = m.coolant[s];
        sr.Double("nut_w_per_k", c.nut_w_per_k, 0, 1e4);
        sr.Double("screw_w_per_m2_k", c.screw_w_per_m2_k, 0, 1e5);
        sr.Double("temperature_offset_c", c.temperature_offset_c, -20, 20);
        sr.RejectUnknown();
      }
    }
    cr.RejectUnknown();
  }
  if (const toml::node* n = r.Node("axis")) {
    auto* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) r.Fail("axis", n, "must be an array of tables ([[axis]])");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::table& at = *(*arr)[i].as_table();
      TomlTableReader ar(at, source, fmt::format("axis[{}]", i));
      AxisDescription a;
      ar.String("name", a.name, true);
      std::transform(a.name.begin(), a.name.end(), a.name.begin(), [](char c) { return std::toupper(c); });
      if (a.name.empty() || a.name.size() > 3 || !std::all_of(a.name.begin(), a.name.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)); }))
        ar.Fail("name", at.get("name"), "must be 1–3 letters such as X");
      if (m.AxisIndex(a.name) >= 0) ar.Fail("name", at.get("name"), "axis '" + a.name + "' is defined twice");
      ar.Double("travel_mm", a.travel_mm, 1, 1e5, true);
      ar.Double("lead_mm", a.lead_mm, 0.5, 200, true);
      std::string fe = "min";
      ar.String("fixed_end", fe);
      if (fe == "min") a.fixed_end = FixedEnd::kMin;
      else if (fe == "max") a.fixed_end = FixedEnd::kMax;
      else ar.Fail("fixed_end", at.get("fixed_end"), "must be \"min\" or \"max\"");
      a.reference_mm = a.fixed_end == FixedEnd::kMin ? 0 : a.travel_mm;
      ar.Double("reference_mm", a.reference_mm, 0, a.travel_mm);
      ar.Double("screw_diameter_mm", a.screw_diameter_mm, 4, 500);
      ar.Double("screw_overhang_mm", a.screw_overhang_mm, 0, 1e4);
      ar.Double("screw_cte_um_per_m_c", a.screw_cte_um_per_m_c, 0, 100);
      ar.Double("backlash_um", a.backlash_um, 0, 1e3);
      ar.Double("homing_repeatability_um", a.homing_repeatability_um, 0, 1e3);
      ar.Double("home_switch_scatter_um", a.home_switch_scatter_um, 0, 1e4);
      ar.Double("home_switch_to_index_mm", a.home_switch_to_index_mm, 0, 200);
      ar.Double("bed_anchor_mm", a.bed_anchor_mm, -1e4, 1e4);
      if (auto* pt = ar.Table("pitch")) {
        TomlTableReader pr(*pt, source, ar.Key("pitch"));
        ReadPitch(pr, a.pitch);
      }
      if (auto* tt = ar.Table("thermal")) {
        TomlTableReader tr(*tt, source, ar.Key("thermal"));
        ReadThermal(tr, a.thermal);
      }
      ar.RejectUnknown();
      m.axes.push_back(std::move(a));
    }
  }
  if (m.axes.empty()) throw InputError(source, 0, "axis", "no [[axis]] defined");
  // [machine] axes lists the axes the file defines: a file cut short at a table boundary is still
  // valid TOML, and would otherwise run with axes (or its sensors) silently missing.
  if (!declared_axes.empty()) {
    std::vector<std::string> defined;
    for (const auto& a : m.axes) defined.push_back(a.name);
    if (defined != declared_axes)
      throw InputError(source, declared_axes_line, "machine.axes",
                       fmt::format("declares axes {} but the file defines [[axis]] {}: is the file cut short?",
                                   fmt::join(declared_axes, ", "), fmt::join(defined, ", ")));
  }
  if (const toml::node* n = r.Node("sensor")) {
    auto* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) r.Fail("sensor", n, "must be an array of tables ([[sensor]])");
    std::set<std::string> names;
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::table& st = *(*arr)[i].as_table();
      TomlTableReader sr(st, source, fmt::format("sensor[{}]", i));
      SensorDescription s;
      sr.String("name", s.name, true);
      if (!ValidSensorName(s.name)) sr.Fail("name", st.get("name"), "must be lower case letters, digits and '_' (e.g. x_nut)");
      if (!names.insert(s.name).second) sr.Fail("name", st.get("name"), "sensor '" + s.name + "' is defined twice");
      std::string kind = "pt100_adc";
      sr.String("kind", kind);
      if (kind == "pt100_adc") s.kind = SensorKind::kPt100Adc;
      else if (kind == "ds18b20") s.kind = SensorKind::kDs18b20;
      else if (kind == "rtd_module") s.kind = SensorKind::kRtdModule;
      else sr.Fail("kind", st.get("kind"), "must be pt100_adc, ds18b20 or rtd_module");
      s.location = s.name;
      sr.String("location", s.location);
      // Location is checked against the thermal nodes here so the line is known.
      bool ok = s.location == "ambient" || s.location == "bed" || s.location == "coolant";
      for (const auto& a : m.axes) {
        std::string p;
        for (char c : a.name) p += static_cast<char>(std::tolower(c));
        for (const char* suffix : {"_nut", "_bearing", "_floating_bearing", "_motor"})
          if (s.location == p + suffix) ok = true;
      }
      if (!ok)
        sr.Fail("location", st.get("location") ? st.get("location") : st.get("name"),
                "unknown location '" + s.location + "' (use <axis>_nut, <axis>_bearing, <axis>_floating_bearing, <axis>_motor, bed, ambient, coolant)");
      sr.Double("offset_c", s.offset_c, -50, 50);
      sr.Double("gain_error", s.gain_error, -0.5, 0.5);
      sr.Double("noise_c", s.noise_c, 0, 10);
      sr.Double("time_constant_s", s.time_constant_s, 0, 1e5);
      sr.RejectUnknown();
      m.sensors.push_back(std::move(s));
    }
  }
  if (const toml::node* n = r.Node("day_fault")) {
    auto* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) r.Fail("day_fault", n, "must be an array of tables ([[day_fault]])");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::table& ft = *(*arr)[i].as_table();
      TomlTableReader fr(ft, source, fmt::format("day_fault[{}]", i));
      DayFaultDescription f;
      fr.String("sensor", f.sensor, true);
      f.source_line = fr.Line(ft.get("sensor"));
      fr.Double("at_h", f.at_h, 0, 24, true);
      fr.String("kind", f.kind);
      const auto kind = ParseSensorFaultKind(f.kind);
      if (!kind || *kind == SensorFaultKind::kNone)
        fr.Fail("kind", ft.get("kind"), fmt::format("'{}' is not a sensor fault (open, short, stuck, drift, spikes)", f.kind));
      fr.RejectUnknown();
      m.day_faults.push_back(std::move(f));
    }
  }
  r.RejectUnknown();
  FinishMachineDescription(m);
  // Checked once the default sensors exist (a file without [[sensor]] still has x_nut, ...).
  for (std::size_t i = 0; i < m.day_faults.size(); ++i) {
    const auto& f = m.day_faults[i];
    const bool known = std::any_of(m.sensors.begin(), m.sensors.end(), [&](const SensorDescription& s) { return s.name == f.sensor; });
    if (!known) {
      std::vector<std::string> names;
      for (const auto& s : m.sensors) names.push_back(s.name);
      throw InputError(source, f.source_line, fmt::format("day_fault[{}].sensor", i),
                       fmt::format("the machine has no sensor '{}' (its sensors: {})", f.sensor, fmt::join(names, ", ")));
    }
  }
  return m;
}

MachineDescription ReadMachineFile(const std::string& path) { return ParseMachineToml(ReadTextFile(path), path); }

void FinishMachineDescription(MachineDescription& m) {
  if (m.axes.empty()) throw InputError(m.source, "machine has no axes");
  if (m.sensors.empty()) {
    for (const auto& a : m.axes) {
      std::string p;
      for (char c : a.name) p += static_cast<char>(std::tolower(c));
      // The seed 000 chain (Pt100 + transmitter + 12-bit card) on nut and
      // bearing seat, a DS18B20 on the motor housing.
      m.sensors.push_back({p + "_nut", SensorKind::kPt100Adc, p + "_nut"});
      m.sensors.push_back({p + "_bearing", SensorKind::kPt100Adc, p + "_bearing"});
      m.sensors.push_back({p + "_motor", SensorKind::kDs18b20, p + "_motor"});
    }
    m.sensors.push_back({"ambient", SensorKind::kRtdModule, "ambient"});
    m.sensors.push_back({"bed", SensorKind::kRtdModule, "bed"});
  }
  // Unset imperfections are drawn from the kind's typical spread with the
  // serial seed: a property of the installed sensor, not of the run.
  std::uint64_t h = m.serial_seed * 0x9E3779B97F4A7C15ull + 0x5151;
  auto next = [&h]() {  // splitmix64 → uniform in (0,1)
    h += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = h;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) / 9007199254740992.0;
  };
  auto normal = [&]() { return std::sqrt(-2 * std::log(next())) * std::cos(2 * M_PI * next()); };
  for (auto& s : m.sensors) {
    double offset_sd, gain_sd, noise, tau;
    switch (s.kind) {
      case SensorKind::kPt100Adc: offset_sd = 0.15; gain_sd = 0.004; noise = 0.02; tau = 20; break;
      case SensorKind::kDs18b20: offset_sd = 0.2; gain_sd = 0.002; noise = 0.01; tau = 30; break;
      default: offset_sd = 0.05; gain_sd = 0.001; noise = 0.008; tau = 15; break;
    }
    double o = normal() * offset_sd, g = normal() * gain_sd;
    if (std::isnan(s.offset_c)) s.offset_c = o;
    if (std::isnan(s.gain_error)) s.gain_error = g;
    if (std::isnan(s.noise_c)) s.noise_c = noise;
    if (std::isnan(s.time_constant_s)) s.time_constant_s = tau;
  }
  for (const auto& a : m.axes)
    if (a.reference_mm < 0 || a.reference_mm > a.travel_mm)
      throw InputError(m.source, 0, "axis " + a.name + ".reference_mm", "must lie within the travel");
}

}  // namespace trueaxis::sim
