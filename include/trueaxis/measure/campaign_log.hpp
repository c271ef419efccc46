#pragma once
// The campaign's temperature log, temperature_log.csv (docs/campaign.md): time_s on the campaign
// clock, date, coolant, <axis>_mm, <axis>_travel_mm and t_<sensor>_c columns (measure::
// CampaignLogHeader). Read by the fit (the thermal history before each laser test) and by
// `campaign check` (which temperatures each test has).
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "trueaxis/core/coolant.hpp"

namespace trueaxis::measure {

struct TemperatureLog {
  std::vector<std::string> sensors;
  std::vector<double> time_s;
  std::vector<int> line;                  // per row: its line in the file, for error messages
  std::vector<std::vector<double>> rows;  // parallel to sensors (NaN: the cell was empty)
  std::vector<CoolantState> coolant;      // per row; empty when the log has no coolant column
  std::map<std::string, std::vector<double>> travel_mm;  // per axis (lower case): <axis>_travel_mm
  int header_line = 0;

  int SensorIndex(std::string_view sensor) const;  // -1 when the log has no such column
};

// Every row must have the header's field count, a time after the previous row's, and plausible
// temperatures: a row cut short or a log glued from two files is refused, not half-read
// (InputError naming the line and column). A log without rows is refused unless `allow_no_rows`
// (a campaign planned but not yet logged).
TemperatureLog ParseTemperatureLog(std::string_view text, const std::string& path, bool allow_no_rows = false);
TemperatureLog ReadTemperatureLog(const std::string& path, bool allow_no_rows = false);

}  // namespace trueaxis::measure
