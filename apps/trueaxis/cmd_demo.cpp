// trueaxis demo [--out DIR] [--seed N] [--fast] [--machine FILE] [--axes X,Y]
// The end-to-end demonstration: campaign → fit → a working day with
// the compensator in its loop → ISO 230-2 before/after → one HTML report.
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/install_paths.hpp"
#include "trueaxis/core/progress.hpp"
#include "trueaxis/demo/demo.hpp"

namespace {

struct Options {
  trueaxis::demo::DemoOptions demo;
  double period_ms = 0;  // 0: 10 ms in process, 100 ms over MODBUS
  bool quiet = false;
};

void Run(Options& o) {
  // The example machine: from the checkout (scripts/demo.sh runs at its root) or the installed examples.
  if (o.demo.machine_file.empty()) o.demo.machine_file = trueaxis::DefaultExampleFile("machines/vmc850.toml");
  o.demo.period_s = (o.period_ms > 0 ? o.period_ms : (o.demo.modbus ? 100 : 10)) / 1000.0;
  if (!std::filesystem::exists(o.demo.machine_file))
    throw trueaxis::InputError(o.demo.machine_file, 0, "--machine", "machine file not found");
  // The demo's steps and results stay; the campaign's events are the status line on a terminal
  // (quiet in a log), the working day's states a line each.
  auto progress = trueaxis::ProgressLine::OnStderr("demo");
  if (!o.quiet)
    o.demo.progress = [&progress](const std::string& line) {
      if (line.rfind("[demo] ", 0) == 0) progress.Note(line.substr(7));
      else if (line.rfind("[campaign] ", 0) == 0) progress.Status(line.substr(11));
      else progress.Event(line);
    };
  std::string why;
  if (!o.demo.IsValid(&why)) throw trueaxis::InputError("command line", why);
  const auto result = trueaxis::demo::RunDemo(o.demo);
  progress.Finish();
  fmt::print("{}", result.BriefReport());
  fmt::print("report: {}\n", result.report_path);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "End-to-end demo on the virtual machine: calibration campaign, model fit, a working day with the "
              "real-time compensator in its loop, ISO 230-2 before/after, HTML report");
  cmd->add_option("--out", opts->demo.out_dir, "Output directory (report.html, model.json, campaign/, day/, history.sqlite)")
      ->capture_default_str();
  cmd->add_option("--seed", opts->demo.seed, "Run seed (the working day uses seed + 1000)")->capture_default_str();
  cmd->add_flag("--fast", opts->demo.fast, "One axis, fewer targets and runs (a few seconds in process; 4–5 minutes with --modbus)");
  cmd->add_option("--machine", opts->demo.machine_file, "Machine description (default: the example machines/vmc850.toml)");
  cmd->add_option("--axes", opts->demo.axes, "Axes to calibrate and measure, e.g. X,Y (default: all; --fast: the first)")
      ->delimiter(',');
  cmd->add_option("--period-ms", opts->period_ms, "Compensation cycle in ms of machine time (default 10; 100 with --modbus)");
  cmd->add_flag("--modbus", opts->demo.modbus,
                "Run the working day over MODBUS TCP on 127.0.0.1: the virtual machine behind the PMC-window/ADAM-6015 "
                "terminal, the compensator on the MODBUS clients. Slow on purpose: every cycle is real round trips, "
                "so the period is 100 ms and --fast takes 4–5 minutes; its figures match the in-process demo at "
                "--period-ms 100, which is what differs from the default 10 ms (docs/runtime.md)");
  cmd->add_option("--modbus-port", opts->demo.modbus_port, "Port of that terminal (default: first free from 15020)");
  cmd->add_flag_function("--no-lag", [opts](std::int64_t) { opts->demo.thermal_lag = false; },
                "Fit the static thermal model (no key-sensor lag), for comparison with the default");
  cmd->add_flag("--coolant-memory", opts->demo.coolant_memory,
                "Let the fit try the coolant memory (one set of gains, the keys drawn to the room under "
                "coolant; fit --coolant-loss-grid-s), off by default since it did worse on the machine zoo "
                "(bench/results/zoo.md)");
  cmd->add_flag("--coolant-soak", opts->demo.coolant_soak,
                "A coolant's own gains keep the off-coolant gains' response to a soak (the sums of the key gains "
                "and shifts held; fit --coolant-soak)");
  cmd->add_flag_function("--no-fallback-models", [opts](std::int64_t) { opts->demo.fallback_models = false; },
                         "Fit no fallback models (fit --no-fallback-models): a key sensor lost in the day "
                         "([[day_fault]]) then leaves its axis the geometric part only");
  cmd->add_option("--fallback-handover-s", opts->demo.compensator.sensor.fallback_handover_s,
                  "A fallback model taking over from a lost key sensor starts from the model's last correction; the "
                  "difference decays with this time constant in s (0: the fallback's own prediction at once)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_flag_function("--no-envelope", [opts](std::int64_t) { opts->demo.fitted_envelope = false; },
                         "Fit without the gains' fitted envelope (fit --envelope-margin -1): gains per coolant state "
                         "and no envelope, the baseline of "
                         "bench/results/zoo.md");
  cmd->add_flag("--rho-fit", opts->demo.rho_fit,
                "Fit ρ from the campaign's room temperatures instead of the screw's CTE (fit --rho-fit), for "
                "comparison: it misses other seasons (bench/results/zoo.md)");
  cmd->add_flag_function("--no-coolant-rest", [opts](std::int64_t) { opts->demo.coolant_rest = false; },
                         "Calibrate without the campaign's stop under coolant (the measurements of the axis at rest "
                         "with the coolant running), for comparison");
  cmd->add_option("--ambient-hours", opts->demo.ambient_hours,
                  "Hours of the day at which the campaign's ambient days measure the idle machine, increasing, e.g. "
                  "14 (default: 3,10,19; bench/results/zoo.md compares)")
      ->delimiter(',');
  cmd->add_option_function<std::vector<int>>(
         "--ambient-days", [opts](const std::vector<int>& days) { opts->demo.ambient_day_offsets = days; },
         "Days after the campaign's first on which it measures the idle machine at another room temperature, e.g. "
         "1,2 for a campaign within one season (default: 60,150, two other seasons)")
      ->delimiter(',');
  cmd->add_option("--other-day", opts->demo.other_day_offset,
                  "The report's other day: this many days after the campaign's first (default 250, another season)")
      ->check(CLI::Range(2, 3650));
  cmd->add_option("--secondary-key-ridge", opts->demo.secondary_key_ridge,
                  "Ridge λ on the bearing key's gain, shrinking it toward the nut-only fit (0: plain least "
                  "squares, for comparison; bench/results/zoo.md)")
      ->capture_default_str();
  cmd->add_option("--key-offsets", opts->demo.key_offsets,
                  "Each key's own pivot: auto (by the fit's cross-validation), on, off (one pivot Px, the fan-shaped model's form; "
                  "bench/results/zoo.md compares)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd->add_option("--motion-heat", opts->demo.motion_heat,
                  "The axis's lagged feed as one more key of the thermal slope (the motion-heat input): auto (kept "
                  "by the fit's cross-validation; the default), on, off (nut and bearing keys only; bench/results/zoo.md compares)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd->add_option("--motion-lag-grid-s", opts->demo.motion_lag_grid_s,
                  "Lag τ values (s) the fit tries for the motion-heat input (with --motion-heat auto or on)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--warmup-per-test", opts->demo.min_warmup_per_test,
                  "The campaign's dry warm-up: each test waits for this many times the last test's duration of "
                  "machining (0: only for the nut's step)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--coolant-prewarm-h", opts->demo.coolant_prewarm_h,
                  "Study: coolant sessions of the campaign, one per value, the flood starting after that many hours of "
                  "dry machining (0: over the cold machine; default 0)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 12.0));
  cmd->add_option_function<std::string>(
         "--coolant-visit",
         [opts](const std::string& v) { opts->demo.coolant_visit = *trueaxis::sim::ParseCoolantVisit(v); },
         std::string("When the campaign measures its coolant sessions: both (the first visit, right after the dry "
                     "warm-ups, and again after the other-season days), first, after-seasons; default ") +
             trueaxis::sim::CoolantVisitName(trueaxis::sim::CampaignOptions{}.coolant_visit))
      ->check(CLI::IsMember({"after-seasons", "first", "both"}));
  cmd->add_option("--keys", opts->demo.keys,
                  "Key sensors: seed (the axis's nut and bearing, the key points of the fan-shaped model), auto (chosen from every "
                  "sensor by the fit's cross-validation, as `trueaxis fit`)")
      ->check(CLI::IsMember({"seed", "auto"}))
      ->capture_default_str();
  cmd->add_flag_function("--no-lag-fall", [opts](std::int64_t) { opts->demo.lag_fall = false; },
                         "Fit one lag τ both ways (no longer lag while a key cools), for comparison");
  cmd->add_flag_function("--raw-temperatures", [opts](std::int64_t) { opts->demo.signal_processing = false; },
                         "Feed the compensator the sensor readings unfiltered (the temperature pipeline's "
                         "filter off; its fault rules still judge every reading, as in `trueaxis run`), for comparison");
  cmd->add_option("--geometric", opts->demo.geometric,
                  "Er(x) model: auto (polynomial or table by cross-validation), polynomial (the fan-shaped model's form), table (one value per sample, as a pitch table)")
      ->check(CLI::IsMember({"auto", "polynomial", "table"}))
      ->capture_default_str();
  cmd->add_flag_function("--fixed-bound", [opts](std::int64_t) { opts->demo.derive_bounds = false; },
                         "Bound every axis's correction by the fixed ±100 µm instead of deriving it from the model "
                         "(saturation is then likely on big machines; the report counts it)");
  cmd->add_option("--controller-limit-um", opts->demo.controller_limit_um,
                  "Largest correction the CNC's compensation input accepts (µm); derived bounds are capped here")
      ->capture_default_str();
  cmd->add_flag("--quiet", opts->quiet, "No progress on stderr");
  cmd->callback([opts] { Run(*opts); });
}

trueaxis::cli::CommandRegistrar reg("demo", Setup);

}  // namespace
