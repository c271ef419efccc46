// trueaxis campaign plan --machine FILE --out DIR [--axes X,Y] [--controller fanuc] [--runs 5] …
// Plans the calibration campaign of a real machine into a campaign folder (docs/real-machine.md).
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "campaign_command.hpp"
#include "command.hpp"
#include "trueaxis/campaign/campaign_plan.hpp"
#include "trueaxis/core/input_error.hpp"

namespace {

using trueaxis::campaign::PlanOptions;

struct Options {
  std::string machine;
  std::vector<std::string> controllers;
  PlanOptions plan;
  std::string coolant_visit = trueaxis::sim::CoolantVisitName(trueaxis::sim::CampaignOptions{}.coolant_visit);
  bool evenly_spaced = false;
  bool no_coolant = false;
};

void Run(Options o) {
  const auto machine = trueaxis::campaign::ReadCampaignMachineFile(o.machine);
  for (const auto& name : o.controllers) {
    if (name == "all") {
      o.plan.controllers = trueaxis::campaign::AllControllers();
      break;
    }
    const auto c = trueaxis::campaign::ParseController(name);
    if (!c)
      throw trueaxis::InputError("command line", 0, "--controller",
                                 fmt::format("'{}' is not linuxcnc, fanuc, sinumerik, heidenhain or all", name));
    o.plan.controllers.push_back(*c);
  }
  o.plan.targets.random_component = !o.evenly_spaced;
  o.plan.schedule.coolant_session = !o.no_coolant;
  o.plan.schedule.coolant_visit = *trueaxis::sim::ParseCoolantVisit(o.coolant_visit);
  const auto plan = trueaxis::campaign::MakeCampaignPlan(machine, o.plan);
  const auto files = trueaxis::campaign::WriteCampaignFolder(plan);
  int tests = 0;
  for (const auto& s : plan.steps) tests += s.max_tests;
  fmt::print(stderr, "planned {} axis(es), {} steps (up to {} laser tests), {} files; read {}/plan.md\n", plan.axes.size(),
             plan.steps.size(), tests, files.size(), o.plan.out_dir);
  fmt::print("{}\n", o.plan.out_dir);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto& p = opts->plan;
  CLI::App* cmd = trueaxis::cli::CampaignCommand(app)->add_subcommand(
      "plan",
      "Plan the calibration campaign of a real machine: states and schedule, ISO 230-2 targets, NC programs, plan.md, "
      "and the empty campaign folder (docs/real-machine.md)");
  cmd->add_option("--machine", opts->machine,
                  "Machine file: the real-machine TOML (docs/real-machine.md) or a virtual machine file "
                  "(docs/machine-file.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", p.out_dir, "Campaign folder to create (refused when it already holds a campaign)")->required();
  cmd->add_option("--axes", p.axes, "Axes to measure, e.g. X,Y (default: all)")->delimiter(',');
  cmd->add_option("--controller", opts->controllers,
                  "Programs for: linuxcnc, fanuc, sinumerik, heidenhain, all (default: the machine file's controller, "
                  "else all)")
      ->delimiter(',');
  cmd->add_option("--runs", p.targets.runs, "Runs of the full laser test (ISO 230-2: 5)")->capture_default_str()->check(CLI::Range(1, 20));
  cmd->add_option("--warm-runs", p.schedule.warm_runs, "Runs of the warm-up, cool-down and coolant tests")
      ->capture_default_str()
      ->check(CLI::Range(2, 20));
  cmd->add_option("--spacing-mm", p.targets.spacing_mm, "Nominal target spacing (at least 5 targets per metre are kept)")
      ->capture_default_str();
  cmd->add_option("--overrun-mm", p.targets.overrun_mm, "Overrun beyond the first and last target for the reversal")
      ->capture_default_str();
  cmd->add_option("--end-clearance-mm", p.targets.end_clearance_mm, "Kept between the overrun and each soft limit")
      ->capture_default_str();
  cmd->add_option("--dwell-s", p.targets.dwell_s, "Stop at each target (settle + laser averaging)")->capture_default_str();
  cmd->add_option("--feed-mm-min", p.targets.feed_mm_min, "Feed between targets")->capture_default_str();
  cmd->add_option("--seed", p.targets.seed, "Seed of the targets' random component; same seed, same targets")
      ->capture_default_str();
  cmd->add_flag("--evenly-spaced", opts->evenly_spaced,
                "Targets evenly spaced, without ISO 230-2's random component (the lead's error is then sampled at few "
                "phases)");
  cmd->add_option("--max-warm", p.schedule.max_warm_measurements, "At most this many warm-up tests per axis")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--max-coolant", p.schedule.max_coolant_measurements, "At most this many tests per coolant warm-up")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--cooldown", p.schedule.cooldown_measurements, "Cool-down tests after saturation (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 20));
  cmd->add_option("--ambient-days", p.schedule.ambient_day_offsets,
                  "Days after the first cold day for the idle machine in another season")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--ambient-hours", p.schedule.ambient_hours, "Hours of those days to measure, increasing")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--coolant-visit", opts->coolant_visit,
                  "Coolant sessions: both (after the dry warm-ups and after the other seasons), first, after-seasons")
      ->check(CLI::IsMember({"after-seasons", "first", "both"}))
      ->capture_default_str();
  cmd->add_flag("--no-coolant", opts->no_coolant, "A dry machine: no coolant sessions");
  cmd->add_option("--start-date", p.start_date, "Date of the first cold day, YYYY-MM-DD (the schedule then shows dates)");
  cmd->callback([opts] { Run(*opts); });
}

trueaxis::cli::CommandRegistrar reg("campaign_plan", Setup);

}  // namespace
