// trueaxis campaign check CAMPAIGN_DIR [--room-c 16,26]
// What a campaign covers and misses, and its file problems (docs/real-machine.md "Check").
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "campaign_command.hpp"
#include "command.hpp"
#include "trueaxis/campaign/campaign_check.hpp"
#include "trueaxis/core/input_error.hpp"

namespace {

struct Options {
  std::string dir;
  std::vector<double> room_c = {trueaxis::campaign::CheckOptions{}.room_low_c,
                                trueaxis::campaign::CheckOptions{}.room_high_c};
};

void Run(const Options& o) {
  if (o.room_c.size() != 2 || !(o.room_c[0] < o.room_c[1]))
    throw trueaxis::InputError("command line", 0, "--room-c", "give the workshop's coldest and warmest room, e.g. 16,26");
  trueaxis::campaign::CheckOptions c;
  c.room_low_c = o.room_c[0];
  c.room_high_c = o.room_c[1];
  const auto result = trueaxis::campaign::CheckCampaign(o.dir, c);
  fmt::print("{}", trueaxis::campaign::CheckReport(result));
  if (!result.file_problems.empty()) throw CLI::RuntimeError(trueaxis::cli::kExitFailure);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = trueaxis::cli::CampaignCommand(app)->add_subcommand(
      "check",
      "What a campaign folder covers (states, nut rise, saturation, seasons, coolant, room range) and misses, and "
      "its file problems; exit 1 when a file has a problem");
  cmd->add_option("CAMPAIGN_DIR", opts->dir, "The campaign folder (manifest.json, temperature_log.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--room-c", opts->room_c,
                  "The room temperatures the machine works in over the year, LOW,HIGH: an end no test reached is "
                  "reported with the test that would reach it")
      ->delimiter(',')
      ->capture_default_str();
  cmd->callback([opts] { Run(*opts); });
}

trueaxis::cli::CommandRegistrar reg("campaign_check", Setup);

}  // namespace
