// trueaxis sim recording --machine FILE --out FILE.csv [--seed N] [--hours H] [--interval-s S]
// A thermal-drift recording of the virtual machine (sensors + true error per axis) in the thermal
// series format, for `trueaxis thermal` (docs/thermal-models.md "Recordings of the virtual machine").
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "sim_command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/thermal_recording.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::cli {
namespace {

struct Options {
  std::string machine;
  std::string out;
  std::uint64_t seed = 1;
  sim::ThermalRecordingOptions recording;
};

void Run(const Options& o) {
  RefuseOutputOverInput(o.out, {o.machine}, "--out");
  std::string why;
  if (!o.recording.IsValid(&why)) throw InputError("command line", 0, "", why);
  sim::VirtualMachine vm(sim::ReadMachineFile(o.machine), o.seed);
  sim::ThermalRecordingOptions ro = o.recording;
  ro.programme_seed = o.seed;
  const sim::ThermalRecording rec = sim::RecordThermalDay(vm, ro);
  thermal::ThermalSeries s;
  s.source = o.out;
  s.has_time = true;
  s.time_s = rec.time_s;
  s.temperature_names = rec.sensor_names;
  s.temperatures_c = rec.temperatures_c;
  s.error_names = rec.error_names;
  s.errors_um = rec.errors_um;
  s.has_coolant = true;
  s.coolant = rec.coolant;
  s.metadata["machine"] = vm.description().name;
  s.metadata["source"] = fmt::format("trueaxis sim recording, seed {}, {} h every {} s; errors are the true error "
                                     "(actual - commanded) at {} of each axis' travel, direction +",
                                     o.seed, ro.hours, ro.interval_s, ro.position_fraction);
  for (std::size_t i = 0; i < rec.programme.size(); ++i) s.metadata[fmt::format("phase_{:02}", i)] = rec.programme[i];
  thermal::WriteThermalSeriesCsv(s, o.out);
  fmt::print(stderr, "{} rows, {} sensors, {} error channels, {} phases\n", s.Rows(), s.temperature_names.size(),
             s.error_names.size(), rec.programme.size());
  fmt::print("{}\n", o.out);
}

void Setup(CLI::App& app) {
  auto* cmd = SimCommand(app)->add_subcommand(
      "recording", "Log the virtual machine's sensors and true axis errors over a drawn working day (thermal series CSV)");
  auto o = std::make_shared<Options>();
  cmd->add_option("--machine", o->machine, "machine description (TOML)")->required();
  cmd->add_option("--out", o->out, "thermal series CSV to write")->required();
  cmd->add_option("--seed", o->seed, "machine noise and the day's programme")->capture_default_str();
  cmd->add_option("--hours", o->recording.hours, "length of the recording")->capture_default_str();
  cmd->add_option("--interval-s", o->recording.interval_s, "logging interval")->capture_default_str();
  cmd->add_option("--position-fraction", o->recording.position_fraction,
                  "where on each axis' travel the error is taken (0..1)")
      ->capture_default_str();
  cmd->callback([o] { Run(*o); });
}

CommandRegistrar reg("sim_recording", Setup);

}  // namespace
}  // namespace trueaxis::cli
