#pragma once
// The logging loop of a campaign on a real machine (docs/campaign.md "On your own machine"): every
// temperature and the CNC's state into the campaign's temperature_log.csv (station::CampaignLogger,
// the fit's layout), and when the next warm-up test is due (campaign::WatchWarmUp), printed live.
// The same loop serves `trueaxis campaign log` (a MODBUS terminal, the terminal's 1-Wire and RTD
// channels, the virtual machine) and `trueaxis-hal --campaign` (LinuxCNC's HAL pins).
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/sim/warmup_rule.hpp"

namespace trueaxis::station {

struct CampaignLogOptions {
  std::string dir;                 // the campaign folder (manifest.json; started when it has none)
  double period_s = 30;            // campaign seconds between two rows, in [1, 3600]
  double duration_s = 0;           // wall-clock seconds, 0: until stopped
  double clock_scale = 0;          // campaign seconds per wall second; 0: the manifest's (1 when none)
  std::vector<std::string> axes;   // axes whose warm-up to watch; empty: every axis with an <axis>_nut sensor
  int max_warm = sim::WarmUpRule{}.max_measurements;
  double warmup_per_test = 0.5;
  bool status = false;             // a status line every row even when stdout is not a terminal
};

// The machine's channels, opened by the caller and left open (the caller closes them).
struct CampaignLogChannels {
  hw::CncLink* link = nullptr;              // nullptr: no CNC (the temperatures only)
  hw::TemperatureSource* source = nullptr;  // required
  std::function<void(double)> advance;      // the virtual machine's clock (wall seconds), else empty
  std::string description;                  // for the start line
};

// Logs until `stop` is set or duration_s has passed; returns the rows appended. Progress and the
// warm-up messages go to stdout. InputError (command line / manifest / log file) for bad options,
// an --axis the machine lacks, a manifest whose clock differs, a log with other columns.
std::size_t RunCampaignLog(const CampaignLogOptions& options, const CampaignLogChannels& channels,
                           const std::atomic<bool>& stop);

}  // namespace trueaxis::station
