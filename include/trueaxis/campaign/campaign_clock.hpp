#pragma once
// The campaign clock (docs/campaign.md): seconds since the campaign's start date (manifest.json
// "start_date"), on which the temperature log's time_s and each measurement's start_time_s are
// counted. On a real machine it is wall time; `clock_scale` (the manifest's "clock_scale", 1 when
// absent) is the machine seconds per wall second of a virtual machine served faster than real time
// (`trueaxis sim serve --time-scale K`), so its campaign logs on the machine's own clock.
//
// Dates are the machine's local time as laser software and CNCs write them:
// "2026-11-28T09:12:00" (a space for the T, fractions of a second, a trailing Z or ±hh:mm offset
// accepted). Without a zone they are read in this computer's time zone.
#include <optional>
#include <string>
#include <string_view>

namespace trueaxis::campaign {

// Seconds since the Unix epoch; nullopt when `text` is not such a date.
std::optional<double> ParseCampaignDate(std::string_view text);
// Local time "YYYY-MM-DDTHH:MM:SS" (with `decimals` digits of the second when > 0).
std::string FormatCampaignDate(double unix_s, int decimals = 0);
// The wall clock now, seconds since the Unix epoch.
double WallClockNowS();

struct CampaignClock {
  double start_unix_s = 0;  // the manifest's start_date
  double scale = 1;         // campaign seconds per wall second
  double FromUnix(double unix_s) const { return (unix_s - start_unix_s) * scale; }
};

}  // namespace trueaxis::campaign
