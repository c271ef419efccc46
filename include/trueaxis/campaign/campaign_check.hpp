#pragma once
// `trueaxis campaign check DIR`: what a campaign folder covers and what it misses (docs/real-machine.md
// "Check"): per axis the states measured (cold, warm-up tests and the nut rise they cover, saturation,
// cool-down, other days and seasons, coolant), the temperatures the tests span (nut, bearing, bed,
// room), the room temperatures the model will be able to vouch for, what is missing and what to
// measure for it — and file problems: a file the manifest lists but is missing or unreadable, a test
// without its time on the campaign clock, a test with no temperatures in the log at its time.
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "trueaxis/measure/campaign_manifest.hpp"
#include "trueaxis/sim/campaign.hpp"

namespace trueaxis::campaign {

struct CheckOptions {
  // The room temperatures the machine works in (the workshop over the year): an end the tests do not
  // reach is reported with the test that would reach it.
  double room_low_c = 16;
  double room_high_c = 26;
  // The rules the warm-up is judged by (saturation window and rise): the virtual campaign's.
  sim::CampaignOptions rules;
};

struct SensorRange {
  std::string sensor;
  std::string location;
  double min_c = 0, max_c = 0;
};

struct AxisCoverage {
  std::string axis;
  std::map<std::string, int> tests;        // state → number of tests
  double max_nut_rise_c = 0;               // over the warm-up tests
  int saturation = -1;                     // 1 reached, 0 not reached, -1 unknown (no log around the last warm test)
  double rise_before_last_warm_c = 0;      // the nut's rise over the saturation window before the last warm test
  std::set<int> ambient_days;              // calendar days after the manifest's start_date of the ambient tests
  std::set<int> ambient_hours;             // their hours of the day
  std::set<std::string> coolants;          // of the coolant and coolant_rest tests
  std::vector<SensorRange> ranges;         // key sensors (nut, bearing, motor, structure, bed, room) over the axis's tests
  double room_min_c = 0, room_max_c = 0;   // NaN when no room reading
  // The CTE of the axis's feedback its files carry (`# cte_um_per_m_c:`, stamped by `campaign add`
  // from the machine file); NaN when none does: the fit then fits the room's soak from these tests.
  double cte_um_per_m_c = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> missing;        // what to measure, one line each
};

struct CampaignCheckResult {
  measure::CampaignManifest manifest;
  std::string manifest_path;
  std::size_t log_rows = 0;
  double log_first_s = 0, log_last_s = 0;
  std::vector<AxisCoverage> axes;
  std::vector<std::string> warm_up_gaps;   // sim::WarmUpCoverageGaps: warm-ups with most of their rise untested
  std::vector<std::string> file_problems;

  bool Complete() const;                   // nothing missing and no file problem
};

// Reads DIR/manifest.json (InputError when it is not a campaign manifest), the temperature log and
// every laser file; problems with those are reported, not thrown.
CampaignCheckResult CheckCampaign(const std::string& dir, const CheckOptions& options);

std::string CheckReport(const CampaignCheckResult& result);

}  // namespace trueaxis::campaign
