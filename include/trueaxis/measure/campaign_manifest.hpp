#pragma once
// The campaign folder's index, manifest.json (docs/campaign.md "manifest.json"): one format for the
// virtual machine's campaign (`sim campaign`) and a campaign on a real machine (`campaign plan` writes
// it empty, `campaign add` appends the laser files, `campaign check` and `fit --manifest` read it).
//
//   {"format": "trueaxis-campaign", "version": 1, "machine": …, "sensors": [...],
//    "temperature_log": "temperature_log.csv", "measurements": [{"file", "axis", "state", "coolant",
//    "sequence", "start_date", "start_time_s", "end_time_s", "nut_rise_c", "mean_temperatures_c"}, …]}
//
// The former name "trueaxis-sim-campaign" (version 1, the same layout) is still read. The campaign
// log beside it, temperature_log.csv, has the columns CampaignLogHeader names.
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace trueaxis::measure {

inline constexpr std::string_view kCampaignManifestFormat = "trueaxis-campaign";
inline constexpr std::string_view kSimCampaignManifestFormat = "trueaxis-sim-campaign";  // still read
inline constexpr int kCampaignManifestVersion = 1;
inline constexpr std::string_view kCampaignManifestFile = "manifest.json";
inline constexpr std::string_view kCampaignLogFile = "temperature_log.csv";

// The states a campaign measures, in the order a campaign takes them (docs/campaign.md):
// cold (overnight soak), warm (warm-up tests as the nut rises, the last at saturation), cooldown,
// ambient (idle machine on another day / season / hour), coolant (warm-up under coolant) and
// coolant_rest (axes stopped, coolant still on).
const std::vector<std::string>& CampaignStates();
bool IsCampaignState(std::string_view state);

struct CampaignEntry {
  std::string file;          // relative to the manifest's folder
  std::string axis;          // upper case, as the machine names it
  std::string state;         // one of CampaignStates()
  std::string coolant = "off";  // off | flood | mist | air, during the measurement
  int sequence = 0;          // 1-based within (axis, state); 0: not numbered
  std::string start_date;    // ISO 8601 local date-time of the start ("" when not known)
  double start_time_s = std::numeric_limits<double>::quiet_NaN();  // campaign clock (seconds since start_date of the manifest)
  double end_time_s = std::numeric_limits<double>::quiet_NaN();
  double nut_rise_c = std::numeric_limits<double>::quiet_NaN();    // mean nut sensor − that of the axis' cold test
  int coolant_session = 0;   // 1-based coolant session through the campaign; 0: a dry state
  // Mean reading of each sensor during the test, in the manifest's sensor order; NaN: never read
  // (written as null).
  std::vector<std::pair<std::string, double>> mean_temperatures_c;

  double MeanTemperatureC(std::string_view sensor) const;  // NaN when absent
};

struct CampaignManifest {
  std::string format = std::string(kCampaignManifestFormat);  // as read; always written as kCampaignManifestFormat
  int version = kCampaignManifestVersion;
  std::string machine;                  // the machine's name
  std::string machine_file;             // the description it was planned / simulated from ("" when none)
  std::optional<std::uint64_t> seed;    // the virtual machine's seed (sim campaigns only)
  std::string start_date;               // campaign clock zero, ISO 8601 ("" until the first log row)
  std::vector<std::string> axes;        // the axes the campaign measures (empty: those of the entries)
  std::vector<std::string> sensors;     // every temperature channel, as in temperature_log.csv
  // Where each sensor sits (docs/machine-file.md locations: <axis>_nut, <axis>_bearing, <axis>_motor,
  // bed, ambient, …). Empty for a sensor whose name is its location.
  std::map<std::string, std::string> sensor_locations;
  std::string temperature_log = std::string(kCampaignLogFile);
  std::vector<CampaignEntry> measurements;  // in the order they were taken

  // The location of `sensor` (its own name when none is recorded).
  std::string LocationOf(const std::string& sensor) const;
  // The sensors at location `location` (e.g. "x_nut", "ambient"), in sensor order.
  std::vector<std::string> SensorsAt(const std::string& location) const;
  // The nut sensor of `axis` (the first at "<axis>_nut"); "" when the machine has none.
  std::string NutSensor(const std::string& axis) const;
};

// Throws InputError(path, 0, "format"/"version", …) unless `doc` names a campaign manifest this build
// reads: "trueaxis-campaign" or "trueaxis-sim-campaign", version 1. A document without "format" (the
// hand-written {"files": [...]} list the fit also reads) passes.
void CheckCampaignManifestFormat(const nlohmann::json& doc, const std::string& path);

// Reads a campaign manifest; InputError(path, line, "measurements[i].field", …) for a missing or
// wrong-typed field, an unknown state or coolant, or a missing format header.
CampaignManifest ParseCampaignManifest(std::string_view text, const std::string& path);
CampaignManifest ReadCampaignManifest(const std::string& path);

// The JSON text (2-space indent, trailing newline); times rounded to 0.1 s, temperatures to 0.001 °C.
std::string CampaignManifestJson(const CampaignManifest& manifest);
void WriteCampaignManifest(const CampaignManifest& manifest, const std::string& path);

// The header of temperature_log.csv: time_s,date,coolant,<axis>_mm…,<axis>_travel_mm…,t_<sensor>_c…
// (axes in lower case), ending with '\n'. The fit reads time_s (campaign clock), coolant, the
// travel columns and the t_<sensor>_c columns (modelfit/fit_input.hpp).
std::string CampaignLogHeader(const std::vector<std::string>& axes, const std::vector<std::string>& sensors);

}  // namespace trueaxis::measure
