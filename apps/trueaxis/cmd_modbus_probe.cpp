// trueaxis modbus probe: reads a machine terminal over MODBUS TCP the way the
// runtime will (ModbusCncLink + ModbusTemperatureSource) and prints what it
// sees: the first thing to run against a new terminal or `trueaxis sim serve`.
//
//   trueaxis modbus probe --port 1502 --rtd-units 2,3
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_connection.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/drivers/register_codec.hpp"

namespace {

using namespace trueaxis;

struct ProbeOptions {
  std::string host = "127.0.0.1";
  int port = 1502;
  int pmc_unit = 1;
  std::vector<std::string> axes;  // names; default A0.. from the window's axis count
  std::vector<int> rtd_units;     // ADAM-6015 unit ids to read (none: skip temperatures)
  int count = 1;
  double interval_s = 1.0;
  double timeout_s = 0.5;
};

CLI::App* ModbusCommand(CLI::App& app) {
  return trueaxis::cli::CommandGroup(app, "modbus", "MODBUS TCP tools (docs/protocols.md)");
}

void RunProbe(const ProbeOptions& o) {
  drivers::ModbusEndpoint ep;
  ep.host = o.host;
  ep.port = o.port;
  ep.response_timeout_s = o.timeout_s;
  ep.reconnect_interval_s = 0;
  std::string why;
  if (!ep.IsValid(&why)) throw InputError("command line", why);
  if (o.count < 1) throw InputError("command line", 0, "--count", "must be >= 1");
  cli::CheckSecondsOption(o.interval_s, "--interval-s", "back to back");

  // Learn the axis count from the window header, then read as the runtime does.
  std::vector<std::string> names = o.axes;
  {
    drivers::ModbusConnection probe(ep);
    std::uint16_t head[2] = {0, 0};
    if (!probe.Ensure(nullptr, true) || !probe.ReadInputRegisters(o.pmc_unit, 0, 2, head))
      throw std::runtime_error(fmt::format("unit {}: {}", o.pmc_unit, probe.last_error()));
    if (head[0] != drivers::pmc::kLayoutVersion)
      throw std::runtime_error(fmt::format("unit {} is not a trueaxis PMC window (layout register reads {})", o.pmc_unit, head[0]));
    if (names.empty())
      for (int a = 0; a < head[1]; ++a) names.push_back(fmt::format("A{}", a));
    if (names.size() != head[1])
      throw InputError("command line", 0, "--axes", fmt::format("{} names given, the window has {} axes", names.size(), head[1]));
  }
  drivers::ModbusCncLinkOptions lo;
  lo.endpoint = ep;
  lo.unit_id = o.pmc_unit;
  lo.axis_names = names;
  drivers::ModbusCncLink link(lo);
  // One source per module: its channel-enable mask (40221) says how many channels it has.
  std::vector<std::unique_ptr<drivers::ModbusTemperatureSource>> rtds;
  for (int unit : o.rtd_units) {
    drivers::ModbusConnection probe(ep);
    std::uint16_t mask = 0;
    if (!probe.Ensure(nullptr, true) || !probe.ReadHoldingRegisters(unit, drivers::adam6015::kChannelEnableAddress, 1, &mask))
      throw std::runtime_error(fmt::format("unit {}: {}", unit, probe.last_error()));
    drivers::ModbusTemperatureSourceOptions to;
    to.endpoint = ep;
    to.unit_ids = {unit};
    for (int c = 0; c < drivers::adam6015::kChannelCount && (mask >> c) & 1; ++c) to.channel_names.push_back(fmt::format("u{}.ch{}", unit, c));
    if (to.channel_names.empty()) continue;
    rtds.push_back(std::make_unique<drivers::ModbusTemperatureSource>(to));
  }
  std::vector<hw::AxisState> axes(names.size());
  std::vector<hw::RawTemperature> temps(drivers::adam6015::kChannelCount);
  for (int i = 0; i < o.count; ++i) {
    // --interval-s is the pause between two probes (each waits for its answers), not a period.
    if (i > 0) std::this_thread::sleep_for(std::chrono::duration<double>(o.interval_s));
    hw::CncState state;
    if (!link.Read(axes, state)) throw std::runtime_error("PMC window: " + link.last_error() + " (or stale / CNC not readable)");
    fmt::print("{}:{} unit {}: heartbeat {}, coolant {}, compensation {}\n", o.host, o.port, o.pmc_unit, link.last_heartbeat(),
               CoolantStateName(state.coolant), state.compensation_enabled ? "enabled" : "DISABLED");
    for (std::size_t a = 0; a < names.size(); ++a)
      fmt::print("  {:<3} {:12.4f} mm  dir {:+d}  programmed {}  {:<7} applied {:+8.1f} um\n", names[a], axes[a].position_mm,
                 axes[a].servo_direction,
                 axes[a].programmed_direction > 0 ? "+" : axes[a].programmed_direction < 0 ? "-" : "?",
                 axes[a].moving ? "moving" : "stopped", link.applied_um()[a]);
    for (auto& rtd : rtds) {
      if (!rtd->Read(temps)) throw std::runtime_error("ADAM-6015: " + rtd->last_error());
      for (std::size_t c = 0; c < rtd->ChannelCount(); ++c) {
        const auto* r = rtd->ChannelRange(c);
        fmt::print("  {:<8} {:8.3f} C {}  [{}]\n", rtd->ChannelName(c), temps[c].temp_c, temps[c].hardware_fault ? "BURN-OUT" : "        ",
                   r ? std::string(r->name) : "?");
      }
    }
    std::fflush(stdout);
  }
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<ProbeOptions>();
  CLI::App* cmd = ModbusCommand(app)->add_subcommand("probe", "Read a machine terminal's PMC window and ADAM-6015 modules once or a few times");
  cmd->add_option("--host", opts->host, "Terminal address")->capture_default_str();
  cmd->add_option("--port", opts->port, "TCP port")->capture_default_str();
  cmd->add_option("--pmc-unit", opts->pmc_unit, "Unit id of the PMC window")->capture_default_str();
  cmd->add_option("--axes", opts->axes, "Axis names, e.g. X,Y,Z (default A0, A1, ...)")->delimiter(',');
  cmd->add_option("--rtd-units", opts->rtd_units, "Unit ids of ADAM-6015 modules to read, e.g. 2,3")->delimiter(',');
  cmd->add_option("--count", opts->count, "Number of reads")->capture_default_str();
  cmd->add_option("--interval-s", opts->interval_s, "Seconds between reads")->capture_default_str();
  cmd->add_option("--timeout-s", opts->timeout_s, "Response timeout")->capture_default_str();
  cmd->callback([opts] { RunProbe(*opts); });
}

trueaxis::cli::CommandRegistrar reg("modbus_probe", Setup);

}  // namespace
