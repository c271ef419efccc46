// trueaxis sim fine --machine FILE --axis X --out FILE.csv [--day N] [--pitch-file F] ...
// A fine calibration cycle (every lead/4) on the virtual machine, optionally
// with a pitch error file applied by the interpolator (docs/pitch-error-file.md).
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "command.hpp"
#include "pitch_command.hpp"
#include "sim_command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/pitch/error_file.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::string machine, axis, out, pitch_file;
  std::uint64_t seed = 1;
  int day = 0;
  cli::FineCliOptions fine;
};

void Run(const Options& o) {
  RefuseOutputOverInput(o.out, {o.machine, o.pitch_file}, "--out");
  const auto machine = sim::ReadMachineFile(o.machine);
  const std::size_t axis = cli::MachineAxis(machine, o.machine, o.axis);
  pitch::FineSessionOptions so;
  so.seed = o.seed;
  so.day = o.day;
  so.cycle = o.fine.Cycle();
  so.interpolator = o.fine.Interpolator();
  so.homing = o.fine.Homing();
  pitch::PitchErrorTable table;
  if (!o.pitch_file.empty()) {
    table = pitch::ReadPitchErrorFile(o.pitch_file);
    if (auto w = pitch::MeasuredRangeWarning(table, o.pitch_file)) fmt::print(stderr, "warning: {}\n", *w);
    if (table.axis != machine.axes[axis].name)
      throw InputError(o.pitch_file, 0, "axis",
                       fmt::format("the file is for axis {}, the cycle runs axis {}", table.axis, machine.axes[axis].name));
    so.table = &table;
  }
  pitch::FineSessionResult r;
  try {
    r = pitch::RunFineSession(machine, axis, so);
  } catch (const std::invalid_argument& e) {
    throw InputError(o.machine, e.what());  // machine and options do not fit together
  }
  const auto dir = std::filesystem::path(o.out).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  measure::WriteMeasurementCsv(r.measurement, o.out);
  const auto ev = analysis::Evaluate(r.measurement);
  fmt::print(stderr, "day {}: homed by {} (reference error {:.3f} um; day 0: {:.3f} um{})\n", o.day,
             sim::HomingMethodName(so.homing), r.homing.offset_um, r.calibration_homing.offset_um,
             r.homing.index_marks_skipped != 0 ? fmt::format(", SKIPPED {} index mark(s)", r.homing.index_marks_skipped) : "");
  fmt::print(stderr, "{}", ev.BriefReport());
  if (so.table)
    fmt::print(stderr, "table applied ({} feed-forward, {} ms cycle){}\n", sim::FeedForwardName(so.interpolator.mode),
               o.fine.cycle_ms,
               r.outside_table_lookups > 0
                   ? fmt::format("\nwarning: the axis moved beyond the range the table was measured over ({}…{} mm); "
                                 "its end values were held there ({} interpolator lookups). On the machine, `run` "
                                 "raises outside_measured_range there: measure the whole travel",
                                 table.VouchedFromMm(), table.VouchedToMm(), r.outside_table_lookups)
                   : "");
  fmt::print("{}\n", o.out);
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::SimCommand(app)->add_subcommand(
      "fine", "Fine calibration cycle (targets every lead/4 over the whole travel, ends included, bidirectional) on the virtual machine");
  cmd->add_option("--machine", o->machine, "Machine description (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--axis", o->axis, "Axis to measure (default: the first)");
  cmd->add_option("--out", o->out, "Measurement CSV to write")->required();
  cmd->add_option("--seed", o->seed, "Run seed (same seed: same laser zero on day 0)")->capture_default_str();
  cmd->add_option("--day", o->day, "0: calibration day (with --pitch-file: right after the calibration, re-homed); "
                  "N: re-homed and measured N days later (laser zero kept)")
      ->capture_default_str()->check(CLI::Range(0, 3650));
  cmd->add_option("--pitch-file", o->pitch_file, "Pitch error file to apply in the interpolator")->check(CLI::ExistingFile);
  o->fine.Add(cmd);
  cmd->callback([o] { Run(*o); });
}

cli::CommandRegistrar reg("sim_fine", Setup);

}  // namespace
