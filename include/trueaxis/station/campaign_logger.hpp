#pragma once
// The temperature log of a campaign on a real machine (`trueaxis campaign log`, docs/campaign.md):
// rows of time_s (campaign clock), date, coolant, <axis>_mm …, <axis>_travel_mm …, t_<sensor>_c …
// in exactly the layout the fit reads, appended to the campaign's temperature_log.csv. A restart
// continues the file: the header must be the same, rows only ever follow the last one in time, and
// each axis's travelled path continues from the last row (never shrinks, whatever the CNC's
// counter did meanwhile).
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::station {

class CampaignLogger {
 public:
  // Opens (or creates) `path` for these channels. InputError(path, line, column) when an existing
  // log has other columns or a bad last row.
  CampaignLogger(std::string path, std::vector<std::string> axis_names, std::vector<std::string> sensor_names);

  std::string Header() const;
  // Rows already in the file when it was opened, and the time of the last one (NaN: none).
  std::size_t ResumedRows() const { return resumed_rows_; }
  double LastTimeS() const { return last_time_s_; }

  // Every poll of the CNC (as often as possible between rows): adds the path each axis travelled
  // since the previous poll — the CNC's distance counter's increase when it reports one (a counter
  // that went back, e.g. a restarted terminal, counts from 0), else the position change.
  void Poll(std::span<const hw::AxisState> axes);

  // Appends one row at campaign time `time_s` (later than the last row, else nothing is written and
  // false returned): the positions and travels of the last Poll. `cnc` nullopt: the CNC could not be
  // read (the coolant keeps its last value); `temperatures` nullopt: they could not be read (empty
  // cells, as a channel the hardware flags).
  bool Append(double time_s, const std::string& date, const std::optional<hw::CncState>& cnc,
              std::optional<std::span<const hw::RawTemperature>> temperatures);

  std::size_t AppendedRows() const { return appended_rows_; }
  const std::vector<double>& TravelMm() const { return travel_mm_; }

 private:
  std::string path_;
  std::vector<std::string> axes_, sensors_;
  std::vector<double> travel_mm_;            // per axis, continued from the file
  std::vector<double> last_counter_mm_;      // the CNC's counter at the previous poll (NaN: none yet)
  std::vector<double> last_position_mm_;     // position at the previous poll (NaN: none yet)
  std::vector<double> position_mm_;          // last known, for the row
  std::string coolant_ = "off";
  double last_time_s_;
  std::size_t resumed_rows_ = 0, appended_rows_ = 0;
};

}  // namespace trueaxis::station
