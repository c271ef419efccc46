// trueaxis sim serve: the virtual machine tool in (scaled) real time behind the
// MODBUS TCP terminal (PMC window + ADAM-6015 RTD modules, docs/protocols.md),
// so a compensator, mbpoll or an HMI reaches it as it would a real machine.
//
//   trueaxis sim serve --machine examples/machines/vmc850.toml --port 1502 --time-scale 60
#include <csignal>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "sim_command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/station/virtual_terminal.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop_requested{false};
extern "C" void OnStopSignal(int) { g_stop_requested.store(true); }

struct ServeOptions {
  std::string machine;
  int port = 1502;
  std::string bind = "127.0.0.1";
  double time_scale = 1.0;
  double duration_s = 0;          // wall seconds; 0 = until SIGINT/SIGTERM
  std::uint64_t seed = 1;
  std::string program = "reciprocate";
  double feed_mm_min = 3000;
  double duty = 0.7;
  std::string coolant = "off";
  double status_interval_s = 5;
  bool json = false;
  double max_compensation_um = 1000;
  int pmc_unit = 1;
  int first_rtd_unit = 2;
  double machine_period_s = 0.005;
  double watchdog_s = 0;
  double watchdog_ramp_um_per_s = 10;
  station::ServedLaser laser;
};

using Status = station::VirtualTerminalStatus;

nlohmann::json StatusJson(const Status& s, double wall_s, const drivers::ModbusMachineServerStats& stats,
                          const std::vector<std::string>& axis_names, const std::vector<std::string>& sensor_names,
                          const char* kind) {
  nlohmann::json j;
  j["kind"] = kind;
  j["wall_s"] = wall_s;
  j["machine_time_s"] = s.machine_time_s;
  j["machine_time"] = s.iso_time;
  j["coolant"] = s.coolant;
  for (std::size_t a = 0; a < axis_names.size(); ++a) {
    j["axes"][axis_names[a]] = {{"commanded_mm", s.commanded_mm[a]},
                                {"actual_mm", s.actual_mm[a]},
                                {"error_um", s.error_um[a]},
                                {"correction_um", s.correction_um[a]}};
  }
  for (std::size_t c = 0; c < sensor_names.size(); ++c) j["temperatures_c"][sensor_names[c]] = s.sensor_c[c];
  j["requests"] = stats.requests;
  j["exceptions"] = stats.exceptions;
  j["clients"] = stats.clients;
  j["compensation_writes"] = stats.compensation_writes;
  return j;
}

std::string StatusText(const Status& s, double wall_s, const drivers::ModbusMachineServerStats& stats,
                       const std::vector<std::string>& axis_names) {
  std::string line = fmt::format("[{:7.1f} s] {} |", wall_s, s.iso_time);
  for (std::size_t a = 0; a < axis_names.size(); ++a)
    line += fmt::format(" {} {:8.3f} mm err {:+6.1f} um corr {:+6.1f} um |", axis_names[a], s.commanded_mm[a], s.error_um[a],
                        s.correction_um[a]);
  line += fmt::format(" {} clients, {} requests, {} writes", stats.clients, stats.requests, stats.compensation_writes);
  return line;
}

void RunServe(const ServeOptions& o) {
  // First thing: a stop request that arrives while the machine is being built
  // must not be lost (a background job starts with SIGINT ignored).
  g_stop_requested.store(false);
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  if (!(o.time_scale > 0 && o.time_scale <= 100000))
    throw InputError("command line", 0, "--time-scale", "must be in (0, 100000]");
  cli::CheckSecondsOption(o.duration_s, "--duration-s", "until stopped");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "none");
  if (o.program != "idle" && o.program != "reciprocate")
    throw InputError("command line", 0, "--program", "'" + o.program + "' is not one of idle, reciprocate");
  if (!(o.duty > 0 && o.duty <= 1)) throw InputError("command line", 0, "--duty", "must be in (0, 1]");
  if (!(o.feed_mm_min > 0 && o.feed_mm_min <= 60000)) throw InputError("command line", 0, "--feed-mm-min", "must be in (0, 60000]");
  const auto coolant = ParseCoolantState(o.coolant);
  if (!coolant) throw InputError("command line", 0, "--coolant", "'" + o.coolant + "' is not one of off, flood, mist, air");

  station::VirtualMachineConfig vc;
  vc.machine_file = o.machine;
  vc.seed = o.seed;
  vc.time_scale = o.time_scale;
  vc.reciprocate = o.program == "reciprocate";
  vc.feed_mm_min = o.feed_mm_min;
  vc.duty = o.duty;
  vc.coolant = *coolant;
  drivers::ModbusMachineServerOptions so;
  so.bind_address = o.bind;
  so.port = o.port;
  so.pmc_unit_id = o.pmc_unit;
  so.first_rtd_unit_id = o.first_rtd_unit;
  so.max_abs_compensation_um = o.max_compensation_um;
  so.machine_period_s = o.machine_period_s;
  so.watchdog_s = o.watchdog_s;
  so.watchdog_ramp_um_per_s = o.watchdog_ramp_um_per_s;
  std::string why;
  if (!so.IsValid(&why)) throw InputError("command line", why);

  station::VirtualTerminal terminal(vc, so);  // throws InputError on a bad machine file
  if (!o.laser.axis.empty()) {
    if (!(o.laser.first_s >= 0) || !(o.laser.every_s > 0))
      throw InputError("command line", 0, "--laser-every-s", "--laser-first-s must be >= 0 and --laser-every-s > 0");
    terminal.SetLaser(o.laser);
  }
  const auto& axis_names = terminal.axis_names();
  const auto& sensor_names = terminal.channel_names();
  const std::size_t n_axes = axis_names.size();
  const double scale = o.time_scale;
  if (auto problem = drivers::UnitIdLayoutProblem(so, sensor_names.size(), true))
    throw InputError("command line", 0, "--first-rtd-unit", *problem);
  terminal.Start();

  const std::size_t modules = terminal.RtdModuleCount();
  if (o.json) {
    nlohmann::json hello;
    hello["kind"] = "listening";
    hello["machine"] = terminal.description().name;
    hello["bind"] = o.bind;
    hello["port"] = o.port;
    hello["pmc_unit"] = o.pmc_unit;
    hello["axes"] = axis_names;
    hello["time_scale"] = scale;
    for (std::size_t c = 0; c < sensor_names.size(); ++c)
      hello["channels"].push_back({{"name", sensor_names[c]}, {"unit", o.first_rtd_unit + static_cast<int>(c / drivers::adam6015::kChannelCount)},
                                    {"channel", c % drivers::adam6015::kChannelCount}});
    fmt::print("{}\n", hello.dump());
  } else {
    fmt::print("trueaxis sim serve: {} ({} axes, {} sensors) on {}:{}, time x{}\n", terminal.description().name, n_axes,
               sensor_names.size(), o.bind, o.port, scale);
    fmt::print("  unit {}: PMC window (axes {})\n", o.pmc_unit, fmt::join(axis_names, ", "));
    for (std::size_t k = 0; k < modules; ++k) {
      std::vector<std::string> names;
      constexpr std::size_t kPerModule = drivers::adam6015::kChannelCount;
      for (std::size_t c = k * kPerModule; c < std::min(sensor_names.size(), (k + 1) * kPerModule); ++c)
        names.push_back(fmt::format("{}={}", c % kPerModule, sensor_names[c]));
      fmt::print("  unit {}: ADAM-6015 channels {}\n", o.first_rtd_unit + static_cast<int>(k), fmt::join(names, " "));
    }
    fmt::print("  registers: docs/protocols.md; stop with Ctrl-C{}\n",
               o.duration_s > 0 ? fmt::format(" (or after {} s)", o.duration_s) : std::string());
  }
  std::fflush(stdout);

  const auto t0 = std::chrono::steady_clock::now();
  auto next_status = t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(o.status_interval_s));
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto print_status = [&](const char* kind) {
    const Status copy = terminal.Status();
    const auto stats = terminal.Stats();
    if (o.json)
      fmt::print("{}\n", StatusJson(copy, wall(), stats, axis_names, sensor_names, kind).dump());
    else
      fmt::print("{}\n", StatusText(copy, wall(), stats, axis_names));
    std::fflush(stdout);
  };
  while (!g_stop_requested.load() && (o.duration_s <= 0 || wall() < o.duration_s)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (o.status_interval_s > 0 && std::chrono::steady_clock::now() >= next_status) {
      print_status("status");
      next_status += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(o.status_interval_s));
    }
  }
  terminal.Stop();
  print_status("final");
  if (!o.json) fmt::print("stopped: {}\n", terminal.Stats().BriefReport());
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<ServeOptions>();
  CLI::App* cmd = trueaxis::cli::SimCommand(app)->add_subcommand(
      "serve", "Run the virtual machine in (scaled) real time behind a MODBUS TCP terminal (docs/protocols.md)");
  cmd->add_option("--machine", opts->machine, "Machine description (TOML, docs/machine-file.md)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--port", opts->port, "TCP port")->capture_default_str()->check(CLI::Range(1, 65535));
  cmd->add_option("--bind", opts->bind, "IPv4 address to listen on")->capture_default_str();
  cmd->add_option("--time-scale", opts->time_scale, "Machine seconds per wall-clock second")->capture_default_str();
  cmd->add_option("--duration-s", opts->duration_s, "Stop after this many wall-clock seconds (0: until Ctrl-C)")->capture_default_str();
  cmd->add_option("--seed", opts->seed, "Run seed (noise, homing, weather)")->capture_default_str();
  cmd->add_option("--program", opts->program, "What the axes do: reciprocate (warm-up duty over 10..90 % of travel) or idle")
      ->capture_default_str();
  cmd->add_option("--feed-mm-min", opts->feed_mm_min, "Feed of the reciprocate program")->capture_default_str();
  cmd->add_option("--duty", opts->duty, "Fraction of time the axes move in the reciprocate program")->capture_default_str();
  cmd->add_option("--coolant", opts->coolant, "Coolant state: off, flood, mist, air")->capture_default_str();
  cmd->add_option("--status-interval-s", opts->status_interval_s, "Wall seconds between status lines (0: none)")->capture_default_str();
  cmd->add_flag("--json", opts->json, "Status lines as JSON objects (one per line)");
  cmd->add_option("--max-compensation-um", opts->max_compensation_um, "Terminal refuses compensation beyond this")->capture_default_str();
  cmd->add_option("--watchdog-s", opts->watchdog_s,
                  "Ramp the compensation to 0 when no client has written for this long (0: hold the last value)")
      ->capture_default_str();
  cmd->add_option("--watchdog-ramp-um-per-s", opts->watchdog_ramp_um_per_s, "Rate of that ramp")->capture_default_str();
  cmd->add_option("--pmc-unit", opts->pmc_unit, "Unit id of the PMC window")->capture_default_str();
  cmd->add_option("--first-rtd-unit", opts->first_rtd_unit, "Unit id of the first ADAM-6015 (7 sensors each)")->capture_default_str();
  cmd->add_option("--laser-axis", opts->laser.axis,
                  "Set up a laser interferometer on this axis: the machine stands until the first (cold) test, then "
                  "runs its program, stopped for a test every --laser-every-s; each test is written as laser software "
                  "writes it (its start date on the wall clock, a time per point, no machine sensors)");
  cmd->add_option("--laser-out", opts->laser.out_dir, "Folder for the laser files (<axis>_laser_<nnn>.csv)");
  cmd->add_option("--laser-first-s", opts->laser.first_s, "Machine seconds before the first test")->capture_default_str();
  cmd->add_option("--laser-every-s", opts->laser.every_s, "Machine seconds from one test's start to the next")
      ->capture_default_str();
  cmd->add_option("--laser-runs", opts->laser.runs, "Runs of each test")->capture_default_str()->check(CLI::Range(2, 20));
  cmd->add_option("--laser-spacing-mm", opts->laser.spacing_mm, "Target spacing")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--laser-count", opts->laser.count, "Tests in all (0: until stopped)")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->callback([opts] { RunServe(*opts); });
}

trueaxis::cli::CommandRegistrar reg("sim_serve", Setup);

}  // namespace
