// trueaxis campaign add CAMPAIGN_DIR FILE --axis X --state cold|warm|… [--coolant flood] [--start DATE | --end DATE]
// One laser file into the campaign: stamped on the campaign clock, the logged temperatures at each
// point, written as canonical CSV into the folder and listed in manifest.json (docs/campaign.md).
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "campaign_command.hpp"
#include "command.hpp"
#include "trueaxis/campaign/campaign_add.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace {

void Setup(CLI::App& app) {
  auto o = std::make_shared<trueaxis::campaign::CampaignAddOptions>();
  CLI::App* cmd = trueaxis::cli::CampaignCommand(app)->add_subcommand(
      "add",
      "Add a laser file to the campaign: its start on the campaign clock, the logged temperatures at each point, "
      "listed in manifest.json for `trueaxis fit` (docs/campaign.md)");
  cmd->add_option("campaign_dir", o->campaign_dir, "The campaign folder (manifest.json, temperature_log.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("file", o->file, "The laser file as the laser software wrote it (canonical CSV or ecmc .dat)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--axis", o->axis, "The measured axis")->required();
  cmd->add_option("--state", o->state, "The machine's state during the test")
      ->required()
      ->check(CLI::IsMember(trueaxis::measure::CampaignStates()));
  cmd->add_option("--coolant", o->coolant, "Coolant during the test: off, flood, mist, air (default: from the log)")
      ->check(CLI::IsMember({"off", "flood", "mist", "air"}));
  cmd->add_option("--start", o->start,
                  "When the test started, e.g. 2026-11-28T09:12:00 (default: the file's '# date:', else its "
                  "modification time as the test's end)");
  cmd->add_option("--end", o->end, "When the test ended (instead of --start)");
  cmd->callback([o] {
    const auto r = trueaxis::campaign::AddToCampaign(*o);
    fmt::print("{}: {} {} #{} from {} to {} s of the campaign clock (start {} from {}){}\n", r.written, o->axis,
               o->state, r.sequence, std::round(r.start_time_s * 10) / 10, std::round(r.end_time_s * 10) / 10,
               r.start_date, r.start_source,
               std::isfinite(r.nut_rise_c) ? fmt::format(", nut {:+.2f} °C vs cold", r.nut_rise_c) : std::string());
  });
}

trueaxis::cli::CommandRegistrar reg("campaign_add", Setup);

}  // namespace
