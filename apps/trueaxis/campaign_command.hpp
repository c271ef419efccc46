#pragma once
// The `trueaxis campaign` parent subcommand: a calibration campaign on a real machine
// (docs/real-machine.md). Its children (plan, log, add, check) attach from their own files.
#include <CLI/CLI.hpp>

#include "command.hpp"

namespace trueaxis::cli {

inline CLI::App* CampaignCommand(CLI::App& app) {
  return CommandGroup(app, "campaign",
                      "A calibration campaign on your own machine: plan it, log temperatures, add laser files, check coverage");
}

}  // namespace trueaxis::cli
