#pragma once
// A campaign folder on disk (docs/campaign.md "Output directory"): manifest.json, the temperature
// log it names and the measurement files it lists — what `trueaxis campaign log` and
// `trueaxis campaign add` read and extend, and what `trueaxis fit` reads.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trueaxis/campaign/campaign_clock.hpp"

namespace trueaxis::campaign {

struct CampaignFolder {
  std::string dir;
  nlohmann::ordered_json manifest;

  std::string ManifestPath() const;
  std::string TemperatureLogPath() const;  // the manifest's "temperature_log", relative to dir
  // The manifest's start_date and clock_scale; InputError naming the manifest when missing or bad.
  CampaignClock Clock() const;
  nlohmann::ordered_json& Measurements();  // the "measurements" array (created when absent)
  void Save() const;                       // writes manifest.json (a temporary file renamed over it)
  // The axis's cte_um_per_m_c from plan.json (`campaign plan`'s copy of the machine file), when the
  // folder has a plan that gives one; nullopt otherwise. InputError naming plan.json when it is
  // not JSON or the value is not a number.
  std::optional<double> PlannedCteUmPerMC(const std::string& axis) const;
};

// Reads DIR/manifest.json; InputError(manifest, 0, field, …) when it is missing, not JSON, or not a
// campaign manifest.
CampaignFolder OpenCampaignFolder(const std::string& dir);

// A new campaign started at `start_unix_s` (no plan written before): manifest.json with the
// format header, the start date, the sensors and the clock scale (when not 1). Not saved yet.
CampaignFolder NewCampaignFolder(const std::string& dir, double start_unix_s, const std::vector<std::string>& sensors,
                                 double clock_scale);

}  // namespace trueaxis::campaign
