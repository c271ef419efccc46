// trueaxis sim campaign --machine FILE --out DIR [--seed N] [--axes X,Y,Z]
// Runs a calibration campaign on the virtual machine (docs/campaign.md).
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "command.hpp"
#include "sim_command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/progress.hpp"
#include "trueaxis/sim/campaign.hpp"

namespace {

struct Options {
  std::string machine;
  std::string out;
  std::uint64_t seed = 1;
  std::vector<std::string> axes;
  int runs = 5;
  int warm_runs = 3;
  double spacing_mm = 25;
  int max_warm = trueaxis::sim::CampaignOptions{}.max_warm_measurements;  // one default, in the library
  int max_coolant = trueaxis::sim::CampaignOptions{}.max_coolant_measurements;
  int cooldown = 2;
  std::vector<int> ambient_days = {60, 150};
  std::vector<double> ambient_hours = trueaxis::sim::CampaignOptions{}.ambient_hours;
  std::vector<double> coolant_prewarm_h = trueaxis::sim::CampaignOptions{}.coolant_prewarm_h;
  std::string coolant_visit = trueaxis::sim::CoolantVisitName(trueaxis::sim::CampaignOptions{}.coolant_visit);
  double warmup_per_test = trueaxis::sim::CampaignOptions{}.min_warmup_per_test;
  bool no_coolant = false;
  bool material_compensation = false;
  bool quiet = false;
};

void Run(const Options& o) {
  auto machine = trueaxis::sim::ReadMachineFile(o.machine);
  trueaxis::sim::CampaignOptions c;
  c.out_dir = o.out;
  c.seed = o.seed;
  c.axes = o.axes;
  c.laser.runs = o.runs;
  c.warm_runs = o.warm_runs;
  c.laser.spacing_mm = o.spacing_mm;
  c.laser.material_compensation = o.material_compensation;
  c.max_warm_measurements = o.max_warm;
  c.max_coolant_measurements = o.max_coolant;
  c.cooldown_measurements = o.cooldown;
  c.ambient_day_offsets = o.ambient_days;
  c.ambient_hours = o.ambient_hours;
  c.coolant_session = !o.no_coolant;
  c.coolant_prewarm_h = o.coolant_prewarm_h;
  c.coolant_visit = *trueaxis::sim::ParseCoolantVisit(o.coolant_visit);
  c.min_warmup_per_test = o.warmup_per_test;
  // On a terminal one status line, rewritten per event; in a log every event on its own line.
  auto progress = trueaxis::ProgressLine::OnStderr("campaign");
  if (!o.quiet) c.progress = [&progress](const std::string& line) { progress.Event(line); };
  std::string why;
  if (!c.IsValid(&why)) throw trueaxis::InputError("command line", why);
  for (const auto& a : o.axes)
    if (machine.AxisIndex(a) < 0) throw trueaxis::InputError(o.machine, 0, "--axes", "the machine has no axis '" + a + "'");
  trueaxis::sim::CampaignSummary summary;
  try {
    summary = trueaxis::sim::RunCampaign(machine, c);
  } catch (const std::invalid_argument& e) {
    // The machine and the options do not fit together (e.g. targets plus
    // overrun longer than an axis' travel): bad input, not a crash.
    throw trueaxis::InputError(o.machine, e.what());
  }
  progress.Finish();
  fmt::print(stderr, "{}", trueaxis::WrapLines(summary.BriefReport()));
  fmt::print("{}\n", o.out);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = trueaxis::cli::SimCommand(app)->add_subcommand(
      "campaign", "Run a calibration campaign (cold, warm-up, other days, coolant) on the virtual machine");
  cmd->add_option("--machine", opts->machine, "Machine description (TOML, docs/machine-file.md)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", opts->out, "Output directory (measurement files, temperature_log.csv, manifest.json)")->required();
  cmd->add_option("--seed", opts->seed, "Run seed (noise, homing, weather); same seed, same files")->capture_default_str();
  cmd->add_option("--axes", opts->axes, "Axes to measure, e.g. X,Y (default: all)")->delimiter(',');
  cmd->add_option("--runs", opts->runs, "Laser runs per measurement (ISO 230-2: 5)")->capture_default_str()->check(CLI::Range(1, 20));
  cmd->add_option("--warm-runs", opts->warm_runs, "Runs of the warm-up and coolant measurements")->capture_default_str()->check(CLI::Range(2, 20));
  cmd->add_option("--spacing-mm", opts->spacing_mm, "Nominal target spacing")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--max-warm", opts->max_warm, "At most this many warm-up measurements per axis")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_option("--max-coolant", opts->max_coolant,
                  "At most this many measurements of the coolant warm-up per axis (the last at saturation)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--cooldown", opts->cooldown, "Cool-down measurements after saturation (0: none)")->capture_default_str()->check(CLI::Range(0, 20));
  cmd->add_option("--ambient-days", opts->ambient_days, "Days after the cold day for the other-ambient measurements")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--ambient-hours", opts->ambient_hours,
                  "Hours of the day at which each ambient day measures the idle machine, increasing (default 3,10,19: "
                  "the room below the warm structure at night, rising, falling; 14: one soaked afternoon, two sets "
                  "of tests shorter; bench/results/zoo.md)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--coolant-prewarm-h", opts->coolant_prewarm_h,
                  "Coolant sessions, one per value: the flood starts after that many hours of dry warm-up machining "
                  "(0: over the cold machine)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(0.0, 12.0));
  cmd->add_option("--coolant-visit", opts->coolant_visit,
                  "When the coolant sessions are measured: both (right after the dry warm-ups and again after the "
                  "other-season days), first, after-seasons")
      ->check(CLI::IsMember({"after-seasons", "first", "both"}))
      ->capture_default_str();
  cmd->add_option("--warmup-per-test", opts->warmup_per_test,
                  "The dry warm-up: each test waits for this many times the last test's duration of machining")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_flag("--no-coolant", opts->no_coolant, "Skip the coolant sessions");
  cmd->add_flag("--material-compensation", opts->material_compensation, "Laser material compensation on (CTE 11.5)");
  cmd->add_flag("--quiet", opts->quiet, "No progress on stderr");
  cmd->callback([opts] { Run(*opts); });
}

trueaxis::cli::CommandRegistrar reg("sim_campaign", Setup);

}  // namespace
