#include "trueaxis/measure/campaign_manifest.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::measure {

const std::vector<std::string>& CampaignStates() {
  static const std::vector<std::string> states = {"cold", "warm", "cooldown", "ambient", "coolant", "coolant_rest"};
  return states;
}

bool IsCampaignState(std::string_view state) {
  const auto& s = CampaignStates();
  return std::find(s.begin(), s.end(), state) != s.end();
}

double CampaignEntry::MeanTemperatureC(std::string_view sensor) const {
  for (const auto& [name, v] : mean_temperatures_c)
    if (name == sensor) return v;
  return std::numeric_limits<double>::quiet_NaN();
}

std::string CampaignManifest::LocationOf(const std::string& sensor) const {
  const auto it = sensor_locations.find(sensor);
  return it == sensor_locations.end() || it->second.empty() ? sensor : it->second;
}

std::vector<std::string> CampaignManifest::SensorsAt(const std::string& location) const {
  std::vector<std::string> out;
  for (const auto& s : sensors)
    if (LocationOf(s) == location) out.push_back(s);
  return out;
}

std::string CampaignManifest::NutSensor(const std::string& axis) const {
  const auto at = SensorsAt(LowerAscii(axis) + "_nut");
  return at.empty() ? std::string() : at.front();
}

void CheckCampaignManifestFormat(const nlohmann::json& doc, const std::string& path) {
  if (!doc.is_object()) return;
  if (doc.contains("format")) {
    const auto& f = doc["format"];
    const bool known = f.is_string() && (f.get<std::string>() == kCampaignManifestFormat ||
                                         f.get<std::string>() == kSimCampaignManifestFormat);
    if (!known)
      throw InputError(path, 0, "format",
                       fmt::format("{} is not \"{}\" (a campaign manifest, docs/campaign.md)", f.dump(),
                                   kCampaignManifestFormat));
  }
  if (doc.contains("version") &&
      !(doc["version"].is_number() && doc["version"].get<double>() == kCampaignManifestVersion))
    throw InputError(path, 0, "version",
                     fmt::format("{} is not supported (this build reads version {})", doc["version"].dump(),
                                 kCampaignManifestVersion));
}

namespace {

class Fields {
 public:
  Fields(const nlohmann::json& obj, std::string path, std::string where)
      : obj_(obj), path_(std::move(path)), where_(std::move(where)) {}

  std::string Name(const char* key) const { return where_.empty() ? key : where_ + "." + key; }
  [[noreturn]] void Fail(const char* key, const std::string& why) const { throw InputError(path_, 0, Name(key), why); }

  std::string String(const char* key, bool required = false) const {
    if (!obj_.contains(key) || obj_[key].is_null()) {
      if (required) Fail(key, "missing (a string)");
      return "";
    }
    if (!obj_[key].is_string()) Fail(key, fmt::format("{} is not a string", obj_[key].dump()));
    return obj_[key].get<std::string>();
  }
  double Number(const char* key) const {  // NaN when absent or null
    if (!obj_.contains(key) || obj_[key].is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!obj_[key].is_number()) Fail(key, fmt::format("{} is not a number", obj_[key].dump()));
    const double v = obj_[key].get<double>();
    if (!std::isfinite(v)) Fail(key, "not a finite number");
    return v;
  }
  int Int(const char* key, int lo, int hi) const {
    const double v = Number(key);
    if (std::isnan(v)) return 0;
    if (v != std::floor(v) || v < lo || v > hi) Fail(key, fmt::format("{} is not a whole number in [{}, {}]", v, lo, hi));
    return static_cast<int>(v);
  }
  std::vector<std::string> Strings(const char* key) const {
    std::vector<std::string> out;
    if (!obj_.contains(key) || obj_[key].is_null()) return out;
    if (!obj_[key].is_array()) Fail(key, "expected an array of strings");
    for (std::size_t i = 0; i < obj_[key].size(); ++i) {
      const auto& v = obj_[key][i];
      if (!v.is_string()) throw InputError(path_, 0, fmt::format("{}[{}]", Name(key), i), "expected a string");
      const std::string s = v.get<std::string>();
      if (std::find(out.begin(), out.end(), s) != out.end())
        throw InputError(path_, 0, fmt::format("{}[{}]", Name(key), i), fmt::format("'{}' is listed twice", s));
      out.push_back(s);
    }
    return out;
  }

 private:
  const nlohmann::json& obj_;
  std::string path_, where_;
};

CampaignEntry ReadEntry(const nlohmann::json& e, const std::string& path, const std::string& where,
                        const std::vector<std::string>& sensors) {
  if (!e.is_object()) throw InputError(path, 0, where, "expected an object with \"file\", \"axis\" and \"state\"");
  const Fields f(e, path, where);
  CampaignEntry out;
  out.file = f.String("file", true);
  if (out.file.empty()) f.Fail("file", "is empty");
  out.axis = f.String("axis", true);
  if (out.axis.empty()) f.Fail("axis", "is empty");
  out.state = f.String("state", true);
  if (!IsCampaignState(out.state))
    f.Fail("state", fmt::format("'{}' is not a campaign state (cold, warm, cooldown, ambient, coolant, coolant_rest)",
                                out.state));
  out.coolant = f.String("coolant");
  if (out.coolant.empty()) out.coolant = "off";
  if (!ParseCoolantState(out.coolant))
    f.Fail("coolant", fmt::format("unknown coolant state '{}' (expected off, flood, mist or air)", out.coolant));
  out.sequence = f.Int("sequence", 0, 100000);
  out.start_date = f.String("start_date");
  out.start_time_s = f.Number("start_time_s");
  out.end_time_s = f.Number("end_time_s");
  if (std::isfinite(out.start_time_s) && std::isfinite(out.end_time_s) && out.end_time_s < out.start_time_s)
    f.Fail("end_time_s", fmt::format("{} s is before the start at {} s", out.end_time_s, out.start_time_s));
  out.nut_rise_c = f.Number("nut_rise_c");
  out.coolant_session = f.Int("coolant_session", 0, 100000);
  if (e.contains("mean_temperatures_c") && !e["mean_temperatures_c"].is_null()) {
    const auto& mt = e["mean_temperatures_c"];
    if (!mt.is_object()) f.Fail("mean_temperatures_c", "expected an object {\"sensor\": °C or null}");
    const Fields t(mt, path, f.Name("mean_temperatures_c"));
    // In the manifest's sensor order, then any other sensor the entry names.
    for (const auto& s : sensors)
      if (mt.contains(s)) out.mean_temperatures_c.emplace_back(s, t.Number(s.c_str()));
    for (const auto& [name, v] : mt.items())
      if (std::find(sensors.begin(), sensors.end(), name) == sensors.end())
        out.mean_temperatures_c.emplace_back(name, t.Number(name.c_str()));
  }
  return out;
}

double Rounded(double v, double scale) { return std::round(v * scale) / scale; }

nlohmann::ordered_json NumberOrNull(double v, double scale) {
  return std::isfinite(v) ? nlohmann::ordered_json(Rounded(v, scale)) : nlohmann::ordered_json(nullptr);
}

}  // namespace

CampaignManifest ParseCampaignManifest(std::string_view text, const std::string& path) {
  const nlohmann::json doc = ParseJsonOrThrow(text, path);
  if (!doc.is_object()) throw InputError(path, 1, "", "expected a JSON object (a campaign manifest, docs/campaign.md)");
  if (!doc.contains("format"))
    throw InputError(path, 0, "format",
                     fmt::format("missing: a campaign manifest starts with \"format\": \"{}\", \"version\": {}",
                                 kCampaignManifestFormat, kCampaignManifestVersion));
  CheckCampaignManifestFormat(doc, path);
  const Fields f(doc, path, "");
  CampaignManifest m;
  m.format = f.String("format");
  m.version = kCampaignManifestVersion;
  m.machine = f.String("machine");
  m.machine_file = f.String("machine_file");
  if (doc.contains("seed") && !doc["seed"].is_null()) {
    if (!doc["seed"].is_number_unsigned()) f.Fail("seed", "expected a whole number >= 0");
    m.seed = doc["seed"].get<std::uint64_t>();
  }
  m.start_date = f.String("start_date");
  m.axes = f.Strings("axes");
  m.sensors = f.Strings("sensors");
  if (doc.contains("sensor_locations") && !doc["sensor_locations"].is_null()) {
    if (!doc["sensor_locations"].is_object()) f.Fail("sensor_locations", "expected an object {\"sensor\": \"location\"}");
    const Fields loc(doc["sensor_locations"], path, "sensor_locations");
    for (const auto& [name, v] : doc["sensor_locations"].items()) {
      if (std::find(m.sensors.begin(), m.sensors.end(), name) == m.sensors.end())
        loc.Fail(name.c_str(), "names a sensor the manifest's \"sensors\" does not list");
      m.sensor_locations[name] = loc.String(name.c_str());
    }
  }
  m.temperature_log = f.String("temperature_log");
  if (m.temperature_log.empty()) m.temperature_log = std::string(kCampaignLogFile);
  if (!doc.contains("measurements")) f.Fail("measurements", "missing (an array, empty before the first test)");
  const auto& list = doc["measurements"];
  if (!list.is_array()) f.Fail("measurements", "expected an array of measurements");
  for (std::size_t i = 0; i < list.size(); ++i)
    m.measurements.push_back(ReadEntry(list[i], path, fmt::format("measurements[{}]", i), m.sensors));
  return m;
}

CampaignManifest ReadCampaignManifest(const std::string& path) { return ParseCampaignManifest(ReadTextFile(path), path); }

std::string CampaignManifestJson(const CampaignManifest& manifest) {
  nlohmann::ordered_json j;
  j["format"] = kCampaignManifestFormat;
  j["version"] = kCampaignManifestVersion;
  j["machine"] = manifest.machine;
  j["machine_file"] = manifest.machine_file;
  if (manifest.seed) j["seed"] = *manifest.seed;
  j["start_date"] = manifest.start_date;
  if (!manifest.axes.empty()) j["axes"] = manifest.axes;
  j["sensors"] = manifest.sensors;
  if (!manifest.sensor_locations.empty()) {
    auto& loc = j["sensor_locations"] = nlohmann::ordered_json::object();
    for (const auto& s : manifest.sensors)
      if (const auto it = manifest.sensor_locations.find(s); it != manifest.sensor_locations.end()) loc[s] = it->second;
  }
  j["temperature_log"] = manifest.temperature_log;
  auto& files = j["measurements"] = nlohmann::ordered_json::array();
  for (const auto& f : manifest.measurements) {
    nlohmann::ordered_json e;
    e["file"] = f.file;
    e["axis"] = f.axis;
    e["state"] = f.state;
    e["coolant"] = f.coolant;
    e["sequence"] = f.sequence;
    e["start_date"] = f.start_date;
    e["start_time_s"] = NumberOrNull(f.start_time_s, 10);
    e["end_time_s"] = NumberOrNull(f.end_time_s, 10);
    e["nut_rise_c"] = NumberOrNull(f.nut_rise_c, 1000);
    if (f.coolant_session > 0) e["coolant_session"] = f.coolant_session;
    auto& mt = e["mean_temperatures_c"] = nlohmann::ordered_json::object();
    for (const auto& [s, v] : f.mean_temperatures_c) mt[s] = NumberOrNull(v, 1000);
    files.push_back(e);
  }
  return j.dump(2) + "\n";
}

void WriteCampaignManifest(const CampaignManifest& manifest, const std::string& path) {
  WriteTextFile(path, CampaignManifestJson(manifest));
}

std::string CampaignLogHeader(const std::vector<std::string>& axes, const std::vector<std::string>& sensors) {
  std::string h = "time_s,date,coolant";
  for (const auto& a : axes) h += "," + LowerAscii(a) + "_mm";
  for (const auto& a : axes) h += "," + LowerAscii(a) + "_travel_mm";
  for (const auto& s : sensors) h += ",t_" + s + "_c";
  return h + "\n";
}

}  // namespace trueaxis::measure
