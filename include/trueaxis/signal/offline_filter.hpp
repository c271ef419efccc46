#pragma once
// Offline use of the TemperatureMonitor: run recorded raw readings through
// exactly the code the real-time loop uses, to tune filter and fault
// parameters on real data and to see what the monitor would have said
// (`trueaxis signal filter`, docs/signal.md).
//
// Readings CSV: a `time_s` column and one column per channel (°C), `#`
// comment lines; an empty cell is a channel not read then (it counts as a
// hardware fault for that sample). Other columns can be skipped by naming
// the channels wanted.
#include <array>
#include <string>
#include <vector>

#include "trueaxis/signal/channel_status.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::signal {

struct ReadingsTable {
  std::string source;
  std::vector<std::string> channels;
  std::vector<double> time_s;
  std::vector<std::vector<double>> values_c;  // [channel][row]
};

// `channels` empty: every column except time_s. Throws InputError naming
// file, line and column.
ReadingsTable ParseReadingsCsv(std::string_view text, const std::string& source,
                               const std::vector<std::string>& channels = {});
ReadingsTable ReadReadingsCsv(const std::string& path, const std::vector<std::string>& channels = {});

struct ChannelSummary {
  std::size_t samples = 0;
  std::size_t spikes_rejected = 0;
  std::size_t status_changes = 0;
  std::array<std::size_t, kChannelStatusCount> samples_in_status{};
  double max_abs_raw_minus_filtered_c = 0;  // over ok samples (large where a spike was removed)
  double rms_raw_minus_filtered_c = 0;      // over ok samples: how much the filter changes the signal overall
};

struct OfflineFilterResult {
  std::vector<std::string> channels;
  std::vector<std::vector<double>> filtered_c;                 // [channel][row]
  std::vector<std::vector<ChannelStatus>> status;              // [channel][row]
  std::vector<ChannelSummary> summary;                         // [channel]
  std::vector<std::string> calibration_without_channel;        // calibrated sensors no column matched (not applied)
  std::string FullReport() const;
};

OfflineFilterResult RunMonitorOffline(const ReadingsTable& table, const MonitorOptions& options,
                                      const CalibrationSet* calibration = nullptr);

// time_s,<ch>_c,<ch>_status,...
std::string FormatOfflineFilterCsv(const ReadingsTable& table, const OfflineFilterResult& result);

}  // namespace trueaxis::signal
