// trueaxis pitch report --before B.csv --after A.csv --pitch-file F --out report.html
//     [--machine M --axis X --feeds 1000,10000,40000]
// Before/after of a pitch table in one HTML page (docs/pitch-error-file.md).
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "pitch_command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_file.hpp"
#include "trueaxis/pitch/error_file.hpp"
#include "trueaxis/pitch/pitch_report.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::string before, after, pitch_file, out, machine, axis;
  std::vector<double> feeds = {1000, 5000, 10000, 20000, 40000};
  double cycle_ms = 2;
  cli::MeasurementInputOptions input;
};

void Run(const Options& o) {
  RefuseOutputOverInput(o.out, {o.before, o.after, o.pitch_file, o.machine, o.input.column_map}, "--out");
  const auto read = o.input.Resolve();
  const auto before = measure::ReadMeasurementFile(o.before, read);
  const auto after = measure::ReadMeasurementFile(o.after, read);
  const auto table = pitch::ReadPitchErrorFile(o.pitch_file);
  if (auto w = pitch::MeasuredRangeWarning(table, o.pitch_file)) fmt::print(stderr, "warning: {}\n", *w);
  pitch::PitchReportInput in;
  in.before = &before;
  in.after = &after;
  in.table = &table;
  if (!o.machine.empty()) {
    const auto machine = sim::ReadMachineFile(o.machine);
    sim::InterpolatorOptions io;
    io.cycle_s = o.cycle_ms / 1000;
    in.following = pitch::FollowingErrorVsFeed(machine, cli::MachineAxis(machine, o.machine, o.axis.empty() ? table.axis : o.axis),
                                               table, o.feeds, io, 1);
  }
  pitch::BuildPitchReport(in).Save(o.out);
  fmt::print("{}\n", o.out);
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::PitchCommand(app)->add_subcommand("report", "HTML before/after of a pitch table (fine runs without and with it)");
  cmd->add_option("--before", o->before, "fine run without the table")->required()->check(CLI::ExistingFile);
  cmd->add_option("--after", o->after, "fine run with the table")->required()->check(CLI::ExistingFile);
  cli::AddMeasurementInputOptions(cmd, o->input);
  cmd->add_option("--pitch-file", o->pitch_file, "the pitch error file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out, "HTML file to write")->required();
  cmd->add_option("--machine", o->machine, "virtual machine: add the following error vs feed (ahead vs late)")->check(CLI::ExistingFile);
  cmd->add_option("--axis", o->axis, "axis of the machine (default: the table's)");
  cmd->add_option("--feeds", o->feeds, "feeds for the following error, mm/min")->delimiter(',')->capture_default_str();
  cmd->add_option("--cycle-ms", o->cycle_ms, "interpolation cycle, ms")->capture_default_str()->check(CLI::Range(0.1, 100.0));
  cmd->callback([o] { Run(*o); });
}

cli::CommandRegistrar reg("pitch_report", Setup);

}  // namespace
