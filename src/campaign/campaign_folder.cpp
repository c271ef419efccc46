#include "trueaxis/campaign/campaign_folder.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::campaign {

std::string CampaignFolder::ManifestPath() const { return (std::filesystem::path(dir) / "manifest.json").string(); }

std::string CampaignFolder::TemperatureLogPath() const {
  std::string name = "temperature_log.csv";
  if (manifest.contains("temperature_log")) {
    if (!manifest["temperature_log"].is_string())
      throw InputError(ManifestPath(), 0, "temperature_log", "expected a file name");
    name = manifest["temperature_log"].get<std::string>();
  }
  std::filesystem::path p(name);
  return (p.is_relative() ? std::filesystem::path(dir) / p : p).string();
}

CampaignClock CampaignFolder::Clock() const {
  CampaignClock c;
  if (!manifest.contains("start_date") || !manifest["start_date"].is_string())
    throw InputError(ManifestPath(), 0, "start_date",
                     "missing: the campaign clock counts from this date (\"2026-11-28T07:00:00\")");
  const std::string text = manifest["start_date"].get<std::string>();
  const auto t = ParseCampaignDate(text);
  if (!t) throw InputError(ManifestPath(), 0, "start_date", fmt::format("'{}' is not a date like 2026-11-28T07:00:00", text));
  c.start_unix_s = *t;
  if (manifest.contains("clock_scale")) {
    const auto& s = manifest["clock_scale"];
    if (!s.is_number() || !(s.get<double>() > 0) || !std::isfinite(s.get<double>()))
      throw InputError(ManifestPath(), 0, "clock_scale", fmt::format("{} is not a number > 0", s.dump()));
    c.scale = s.get<double>();
  }
  return c;
}

std::optional<double> CampaignFolder::PlannedCteUmPerMC(const std::string& axis) const {
  const std::string path = (std::filesystem::path(dir) / "plan.json").string();
  if (!std::filesystem::exists(path)) return std::nullopt;
  const nlohmann::json plan = ParseJsonOrThrow(ReadTextFile(path), path);
  if (!plan.contains("axes") || !plan["axes"].is_array()) return std::nullopt;
  for (const auto& a : plan["axes"]) {
    if (!a.is_object() || a.value("axis", std::string()) != axis || !a.contains("cte_um_per_m_c")) continue;
    const auto& v = a["cte_um_per_m_c"];
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw InputError(path, 0, "axes." + axis + ".cte_um_per_m_c", fmt::format("{} is not a number", v.dump()));
    return v.get<double>();
  }
  return std::nullopt;
}

nlohmann::ordered_json& CampaignFolder::Measurements() {
  auto& m = manifest["measurements"];
  if (m.is_null()) m = nlohmann::ordered_json::array();
  if (!m.is_array()) throw InputError(ManifestPath(), 0, "measurements", "expected an array");
  return m;
}

void CampaignFolder::Save() const {
  const std::string path = ManifestPath();
  const std::string tmp = path + ".tmp";
  WriteTextFile(tmp, manifest.dump(2) + "\n");
  std::filesystem::rename(tmp, path);
}

CampaignFolder OpenCampaignFolder(const std::string& dir) {
  CampaignFolder f;
  f.dir = dir;
  const std::string path = f.ManifestPath();
  if (!std::filesystem::exists(path))
    throw InputError(path, 0, "", "no manifest.json in the campaign folder (trueaxis campaign plan or campaign log starts one)");
  const std::string text = ReadTextFile(path);
  measure::CheckCampaignManifestFormat(ParseJsonOrThrow(text, path), path);  // a JSON error with its line
  f.manifest = nlohmann::ordered_json::parse(text);
  if (!f.manifest.is_object()) throw InputError(path, 0, "", "expected a JSON object (a campaign manifest)");
  return f;
}

CampaignFolder NewCampaignFolder(const std::string& dir, double start_unix_s, const std::vector<std::string>& sensors,
                                 double clock_scale) {
  CampaignFolder f;
  f.dir = dir;
  auto& j = f.manifest;
  j["format"] = std::string(measure::kCampaignManifestFormat);
  j["version"] = measure::kCampaignManifestVersion;
  j["start_date"] = FormatCampaignDate(start_unix_s);
  if (clock_scale != 1) j["clock_scale"] = clock_scale;
  j["sensors"] = sensors;
  j["temperature_log"] = "temperature_log.csv";
  j["measurements"] = nlohmann::ordered_json::array();
  return f;
}

}  // namespace trueaxis::campaign
