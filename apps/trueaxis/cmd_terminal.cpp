// trueaxis terminal: the machine's own terminal (seed 003) on real hardware.
// Reads DS18B20 sensors on the Linux 1-Wire bus and RTD modules over MODBUS
// TCP, optionally relays a CNC reached over MODBUS, and serves everything on
// the register map the workshop server polls (docs/protocols.md), with the
// watchdog that ramps the compensation to zero when the server goes quiet.
//
//   trueaxis terminal --config terminal.toml [--duration-s 10] [--json]
// Config and wiring: docs/terminal.md.
#include <csignal>
#include <filesystem>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/terminal/terminal_config.hpp"
#include "trueaxis/terminal/terminal_sources.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop_requested{false};
extern "C" void OnTerminalStopSignal(int) { g_stop_requested.store(true); }

struct TerminalCliOptions {
  std::string config;
  int port = 0;             // 0: the config's
  std::string bind;         // "": the config's
  std::string one_wire_root;  // "": the config's
  double duration_s = 0;
  double status_interval_s = 5;
  bool json = false;
};

// What the status lines show about one channel, read from the thread-safe
// sides of the sources (never through the machine thread's objects).
struct ChannelView {
  std::string name;
  int unit = 0;
  int index = 0;
  double temp_c = NAN;
  std::string state;
  const terminal::OneWireChannelStatus* one_wire = nullptr;  // the DS18B20's counters (1-Wire channels only)
};

class TerminalView {
 public:
  TerminalView(std::vector<terminal::PolledTemperatureSource*> parts, terminal::OneWireTemperatureSource* one_wire,
               const std::vector<std::string>& names, int first_rtd_unit)
      : parts_(std::move(parts)), one_wire_(one_wire) {
    for (std::size_t i = 0; i < names.size(); ++i)
      channels_.push_back({names[i], first_rtd_unit + static_cast<int>(i / drivers::adam6015::kChannelCount),
                           static_cast<int>(i % drivers::adam6015::kChannelCount), NAN, ""});
  }

  const std::vector<ChannelView>& Refresh() {
    std::size_t offset = 0;
    for (std::size_t p = 0; p < parts_.size(); ++p) {
      std::vector<hw::RawTemperature> raw(parts_[p]->ChannelCount());
      const bool ok = parts_[p]->Read(raw);
      const bool is_one_wire = p == 0 && one_wire_;
      if (is_one_wire) one_wire_status_ = one_wire_->StatusSnapshot();
      static const std::vector<terminal::OneWireChannelStatus> kNone;
      const auto& w1 = is_one_wire ? one_wire_status_ : kNone;
      for (std::size_t c = 0; c < raw.size(); ++c) {
        ChannelView& v = channels_[offset + c];
        const bool fault = !ok || raw[c].hardware_fault || !std::isfinite(raw[c].temp_c);
        v.temp_c = fault ? NAN : raw[c].temp_c;
        v.one_wire = w1.empty() ? nullptr : &w1[c];
        if (!w1.empty()) v.state = terminal::OneWireChannelStateName(w1[c].state);
        else v.state = !ok ? "offline" : fault ? "fault" : "ok";
      }
      offset += raw.size();
    }
    return channels_;
  }

 private:
  std::vector<terminal::PolledTemperatureSource*> parts_;
  terminal::OneWireTemperatureSource* one_wire_;
  std::vector<terminal::OneWireChannelStatus> one_wire_status_;  // the 1-Wire part is the first: its snapshot stays valid
  std::vector<ChannelView> channels_;
};

nlohmann::json StatusJson(const char* kind, double wall_s, const std::vector<ChannelView>& channels,
                          const drivers::ModbusMachineServerStats& stats) {
  nlohmann::json j;
  j["kind"] = kind;
  j["wall_s"] = wall_s;
  for (const auto& c : channels) {
    nlohmann::json ch = {{"name", c.name}, {"unit", c.unit}, {"channel", c.index}, {"state", c.state}};
    ch["temp_c"] = std::isfinite(c.temp_c) ? nlohmann::json(c.temp_c) : nlohmann::json(nullptr);  // null = UNAVAILABLE
    if (c.one_wire) {
      ch["good_reads"] = c.one_wire->good_reads;
      ch["failed_reads"] = c.one_wire->failed_reads;
      ch["power_on_refused"] = c.one_wire->power_on_refused;
      ch["losses"] = c.one_wire->losses;
      if (!c.one_wire->detail.empty()) ch["detail"] = c.one_wire->detail;
    }
    j["channels"].push_back(ch);
  }
  j["requests"] = stats.requests;
  j["clients"] = stats.clients;
  j["compensation_writes"] = stats.compensation_writes;
  j["watchdog_steps"] = stats.watchdog_steps;
  return j;
}

std::string StatusText(double wall_s, const std::vector<ChannelView>& channels, const drivers::ModbusMachineServerStats& stats) {
  std::string line = fmt::format("[{:6.1f} s]", wall_s);
  for (const auto& c : channels)
    line += std::isfinite(c.temp_c) ? fmt::format(" {} {:.3f} °C |", c.name, c.temp_c) : fmt::format(" {} UNAVAILABLE ({}) |", c.name, c.state);
  line += fmt::format(" {} clients, {} requests, {} writes", stats.clients, stats.requests, stats.compensation_writes);
  return line;
}

void RunTerminal(const TerminalCliOptions& o) {
  g_stop_requested.store(false);
  std::signal(SIGINT, OnTerminalStopSignal);
  std::signal(SIGTERM, OnTerminalStopSignal);
  cli::CheckSecondsOption(o.duration_s, "--duration-s", "until stopped");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "none");
  terminal::TerminalConfig cfg = terminal::ReadTerminalConfig(o.config);
  if (o.port > 0) cfg.server.port = o.port;
  if (!o.bind.empty()) cfg.server.bind_address = o.bind;
  if (!o.one_wire_root.empty()) {
    if (!cfg.one_wire.present) throw InputError("command line", 0, "--one-wire-root", "the config has no [one_wire] section");
    cfg.one_wire.options.root = o.one_wire_root;
  }
  if (cfg.one_wire.present) {
    // The kernel's 1-Wire tree: a file there is a mistake; a missing one is the bus driver not loaded
    // (yet: it may appear after boot), which left every channel never_read without a word.
    const std::string& root = cfg.one_wire.options.root;
    std::error_code ec;
    const bool from_option = !o.one_wire_root.empty();
    if (std::filesystem::exists(root, ec) && !std::filesystem::is_directory(root, ec))
      throw InputError(from_option ? "command line" : o.config, 0, from_option ? "--one-wire-root" : "one_wire.root",
                       fmt::format("'{}' is a file, not the 1-Wire devices directory (on the terminal: /sys/bus/w1/devices)", root));
    if (!std::filesystem::exists(root, ec))
      fmt::print(stderr,
                 "warning: the 1-Wire devices directory '{}' does not exist (the w1-gpio / w1-therm drivers not loaded?): "
                 "every 1-Wire channel reads as lost until it appears\n",
                 root);
  }

  terminal::TerminalSources sources = terminal::BuildTerminalSources(cfg);
  terminal::CombinedTemperatureSource& temperatures = *sources.combined;
  terminal::OneWireTemperatureSource* one_wire = sources.one_wire;
  std::string why;
  if (!temperatures.Configure(&why)) throw InputError(o.config, why);
  std::unique_ptr<drivers::ModbusCncLink> cnc;
  if (cfg.cnc == terminal::CncKind::kModbus) {
    cnc = std::make_unique<drivers::ModbusCncLink>(cfg.cnc_link);
    if (!cnc->Configure(&why)) throw InputError(o.config, 0, "cnc", why);
  }

  const auto names = cfg.ChannelNames();
  if (!o.json) {
    fmt::print("trueaxis terminal: {} on {}:{}\n", o.config, cfg.server.bind_address, cfg.server.port);
    if (cnc)
      fmt::print("  unit {}: PMC window relayed from the CNC at {}:{} unit {} (axes {}), watchdog {} s\n", cfg.server.pmc_unit_id,
                 cfg.cnc_link.endpoint.host, cfg.cnc_link.endpoint.port, cfg.cnc_link.unit_id, fmt::join(cfg.cnc_link.axis_names, ", "),
                 cfg.server.watchdog_s);
    else
      fmt::print("  no CNC (cnc = \"none\"): temperatures only, unit {} absent\n", cfg.server.pmc_unit_id);
    for (std::size_t i = 0; i < names.size(); ++i)
      fmt::print("  unit {} channel {}: {}\n", cfg.server.first_rtd_unit_id + static_cast<int>(i / drivers::adam6015::kChannelCount),
                 i % drivers::adam6015::kChannelCount, names[i]);
    if (one_wire) {
      const auto unmapped = one_wire->UnmappedSensors();
      if (!unmapped.empty()) fmt::print("  note: DS18B20 sensors on the bus that no channel names: {}\n", fmt::join(unmapped, ", "));
    }
  }
  // Activation failures (an RTD module or the CNC not reachable yet) are not
  // fatal: the sources retry on their own and the registers say offline.
  if (!temperatures.Activate(&why)) fmt::print(stderr, "terminal: temperatures: {} (retrying)\n", why);
  if (cnc && !cnc->Activate(&why)) fmt::print(stderr, "terminal: cnc: {} (retrying)\n", why);

  if (auto problem = drivers::UnitIdLayoutProblem(cfg.server, temperatures.ChannelCount(), cnc != nullptr)) {
    temperatures.Deactivate();
    throw InputError(o.config, 0, "serve.first_rtd_unit_id", *problem);
  }
  drivers::ModbusMachineServer server(cnc.get(), &temperatures, cfg.server);
  if (!server.Start(&why)) {
    temperatures.Deactivate();
    throw std::runtime_error(why);
  }
  if (o.json) {
    nlohmann::json hello = {{"kind", "listening"}, {"bind", cfg.server.bind_address}, {"port", cfg.server.port},
                            {"channels", names}, {"cnc", cnc ? "modbus" : "none"}};
    fmt::print("{}\n", hello.dump());
  }
  std::fflush(stdout);

  TerminalView view(sources.parts, one_wire, names, cfg.server.first_rtd_unit_id);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  double next_status = o.status_interval_s;
  auto print_status = [&](const char* kind) {
    const auto& channels = view.Refresh();
    const auto stats = server.Stats();
    if (o.json) fmt::print("{}\n", StatusJson(kind, wall(), channels, stats).dump());
    else fmt::print("{}\n", StatusText(wall(), channels, stats));
    std::fflush(stdout);
  };
  while (!g_stop_requested.load() && (o.duration_s <= 0 || wall() < o.duration_s)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (o.status_interval_s > 0 && wall() >= next_status) {
      print_status("status");
      next_status += o.status_interval_s;
    }
  }
  server.Stop();
  print_status("final");
  temperatures.Deactivate();
  if (cnc) cnc->Deactivate();
  if (!o.json) fmt::print("stopped: {}\n", server.Stats().BriefReport());
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<TerminalCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "terminal", "Run a machine's terminal: DS18B20 (1-Wire) and RTD (MODBUS) sensors served on the register map (docs/terminal.md)");
  cmd->add_option("--config", opts->config, "Terminal configuration (TOML, docs/terminal.md)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--port", opts->port, "TCP port (overrides [serve] port)")->check(CLI::Range(1, 65535));
  cmd->add_option("--bind", opts->bind, "IPv4 address to listen on (overrides [serve] bind)");
  cmd->add_option("--one-wire-root", opts->one_wire_root, "1-Wire devices directory (overrides [one_wire] root)");
  cmd->add_option("--duration-s", opts->duration_s, "Stop after this many seconds (0: until Ctrl-C)")->capture_default_str();
  cmd->add_option("--status-interval-s", opts->status_interval_s, "Seconds between status lines (0: none)")->capture_default_str();
  cmd->add_flag("--json", opts->json, "Status lines as JSON objects (one per line)");
  cmd->callback([opts] { RunTerminal(*opts); });
}

trueaxis::cli::CommandRegistrar reg("terminal", Setup);

}  // namespace
