#pragma once
// trueaxis-hal --campaign DIR: the campaign's temperature log from LinuxCNC (docs/linuxcnc.md
// "Campaign log from HAL"): the run configuration's axes and channels, read from HAL pins (and the
// RTD modules over MODBUS, or temperature pins), logged by the loop of `trueaxis campaign log`
// (station::RunCampaignLog) into DIR/temperature_log.csv, with the warm-up messages. It writes no
// correction (the eoffset pins stay at zero counts).
#include <string>

#include <CLI/CLI.hpp>

#include "trueaxis/station/campaign_log_loop.hpp"

namespace trueaxis::hal_app {

// --campaign DIR and the log's options (--campaign-period-s, --campaign-duration-s, --campaign-axis,
// --max-warm, --warmup-per-test) into `options`.
void AddCampaignOptions(CLI::App& app, station::CampaignLogOptions& options);

// Runs the component `name` as the campaign logger until SIGTERM/SIGINT (halcmd unloadusr) or the
// duration; 0 when stopped. Throws InputError for a bad configuration or campaign folder.
int RunHalCampaignLog(const std::string& config_path, const std::string& name, bool temperatures_from_hal,
                      const station::CampaignLogOptions& options);

}  // namespace trueaxis::hal_app
