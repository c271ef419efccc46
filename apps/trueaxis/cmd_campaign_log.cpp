// trueaxis campaign log CAMPAIGN_DIR --config RUN_OR_TERMINAL_CONFIG [--period-s 30] [--duration-s S]
// Records the machine's temperatures and CNC state into the campaign's temperature_log.csv
// (docs/campaign.md "On your own machine") and says when the next warm-up test is due. The loop is
// station::RunCampaignLog (also behind `trueaxis-hal --campaign`); this file opens the channels.
#include <atomic>
#include <csignal>
#include <functional>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "campaign_command.hpp"
#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/station/campaign_log_loop.hpp"
#include "trueaxis/station/machine_connection.hpp"
#include "trueaxis/terminal/terminal_config.hpp"
#include "trueaxis/terminal/terminal_sources.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop{false};
extern "C" void OnCampaignLogSignal(int) { g_stop.store(true); }

struct Options {
  std::string config;
  station::CampaignLogOptions log;
};

// The machine's channels, opened by the wiring `trueaxis run` uses (a run config: the MODBUS
// terminal or the virtual machine) or by the terminal's own (terminal.toml: 1-Wire and RTD modules,
// the CNC over MODBUS when it has one). Raw readings: the log is the record, not the filtered signal.
struct Channels {
  station::Machine machine;
  terminal::TerminalSources terminal_sources;
  std::unique_ptr<drivers::ModbusCncLink> terminal_cnc;
  hw::CncLink* link = nullptr;
  hw::TemperatureSource* source = nullptr;
  std::function<void(double)> advance;
  std::string description;
  void Close() {
    if (link) link->Deactivate();
    if (source) source->Deactivate();
  }
};

Channels OpenChannels(const std::string& path) {
  Channels ch;
  const toml::table root = ParseTomlOrThrow(ReadTextFile(path), path);
  std::string why;
  if (root.contains("machine")) {
    station::SiteConfig c = station::ReadSiteConfig(path, /*model_required=*/false);
    c.installation.signal_processing = false;
    ch.machine = station::OpenMachine(c);
    for (const auto& w : ch.machine.warnings) fmt::print(stderr, "warning: {}\n", w);
    ch.link = ch.machine.link;
    ch.source = ch.machine.source;
    ch.advance = ch.machine.advance;
    ch.description = ch.machine.description;
    return ch;
  }
  terminal::TerminalConfig cfg = terminal::ReadTerminalConfig(path);
  ch.terminal_sources = terminal::BuildTerminalSources(cfg);
  ch.source = ch.terminal_sources.combined.get();
  if (!ch.source->Configure(&why)) throw InputError(path, why);
  if (!ch.source->Activate(&why)) fmt::print(stderr, "warning: temperatures: {} (retrying)\n", why);
  if (cfg.cnc == terminal::CncKind::kModbus) {
    ch.terminal_cnc = std::make_unique<drivers::ModbusCncLink>(cfg.cnc_link);
    if (!ch.terminal_cnc->Configure(&why)) throw InputError(path, 0, "cnc", why);
    if (!ch.terminal_cnc->Activate(&why)) fmt::print(stderr, "warning: cnc: {} (retrying)\n", why);
    ch.link = ch.terminal_cnc.get();
  }
  ch.description = fmt::format("the terminal's channels ({})", path);
  return ch;
}

void Run(const Options& o) {
  g_stop.store(false);
  std::signal(SIGINT, OnCampaignLogSignal);
  std::signal(SIGTERM, OnCampaignLogSignal);
  cli::CheckSecondsOption(o.log.duration_s, "--duration-s", "until stopped");
  Channels ch = OpenChannels(o.config);
  station::CampaignLogChannels channels{ch.link, ch.source, ch.advance, ch.description};
  try {
    station::RunCampaignLog(o.log, channels, g_stop);
  } catch (...) {
    ch.Close();
    throw;
  }
  ch.Close();
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::CampaignCommand(app)->add_subcommand(
      "log",
      "Record every temperature, each axis's position and travelled path and the coolant into the campaign's "
      "temperature_log.csv, and say when the next warm-up test is due (docs/campaign.md)");
  cmd->add_option("campaign_dir", o->log.dir, "The campaign folder (manifest.json; started now when it has none)")->required();
  cmd->add_option("--config", o->config,
                  "A run config (trueaxis run: the MODBUS terminal or the virtual machine; [model] may be left out) or "
                  "the terminal's terminal.toml (its 1-Wire and RTD channels, its CNC)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--period-s", o->log.period_s, "Seconds of the campaign clock between two rows")->capture_default_str();
  cmd->add_option("--duration-s", o->log.duration_s, "Stop after this many wall-clock seconds (0: until Ctrl-C)")
      ->capture_default_str();
  cmd->add_option("--axis", o->log.axes, "Axes whose warm-up to watch (default: every axis with a <axis>_nut sensor)")
      ->delimiter(',');
  cmd->add_option("--max-warm", o->log.max_warm, "At most this many warm-up tests per axis (the last at saturation)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--warmup-per-test", o->log.warmup_per_test,
                  "Each warm-up test also waits for this many times the last test's duration of machining")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--clock-scale", o->log.clock_scale,
                  "Campaign seconds per wall second: only for a virtual machine served faster than real time (sim "
                  "serve --time-scale K); kept in manifest.json");
  cmd->add_flag("--status", o->log.status, "A status line every row even when the output is not a terminal");
  cmd->callback([o] { Run(*o); });
}

cli::CommandRegistrar reg("campaign_log", Setup);

}  // namespace
