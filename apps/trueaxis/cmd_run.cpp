// trueaxis run --config FILE.toml [--duration-s S] [--quiet] [--web HOST:PORT --users FILE]
// Runs the real-time compensator against the configured machine — the
// virtual machine in process, or a CNC terminal and RTD modules over MODBUS
// TCP — until SIGINT/SIGTERM or the duration, logging to the history
// database and/or a CSV file (docs/runtime.md). With --web, the machine is also served to the
// browser behind a login (docs/web.md).
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/cycle_log.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/station/machine_connection.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/store/open_history_sink.hpp"
#include "trueaxis/web/coolant_override_link.hpp"
#include "trueaxis/web/run_backend.hpp"
#include "web_front_end.hpp"

namespace {

using namespace trueaxis;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void RunCommandOnStopSignal(int) { g_stop.store(true); }

struct Options {
  std::string config;
  double duration_s = 0;
  bool duration_given = false;  // else the config's
  double status_interval_s = 5;
  bool quiet = false;
  cli::WebCliOptions web;
  std::string machine_id = "machine";
  bool machine_id_given = false;
  std::string iso_dir = "auto";  // laser test pairs for the web page's ISO figures
};

void Run(const Options& o) {
  if (o.duration_given) cli::CheckSecondsOption(o.duration_s, "--duration-s", "until SIGINT/SIGTERM");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "every 50 ms");
  station::SiteConfig site = station::ReadSiteConfig(o.config);
  station::InstallationConfig& c = site.installation;
  if (o.duration_given) c.duration_s = o.duration_s;
  station::Machine m = station::OpenMachine(site, /*with_pipeline=*/false);  // the hardware
  for (const auto& w : m.warnings) fmt::print(stderr, "warning: {}\n", w);
  // The coolant state the compensator sees can be forced from the web page.
  web::CoolantOverrideLink link(*m.link);
  // The installation: the temperature pipeline ([signal], on by default), the compensator and the
  // model — InputError (exit 2) on a model that does not fit the machine — and its record
  // ([history]: the history database, the CSV log).
  station::Installation installation(c, link, *m.source, m.Clock(), m.name);
  for (const auto& w : installation.warnings()) fmt::print(stderr, "warning: {}\n", w);
  runtime::Compensator* comp = &installation.compensator();
  const double unix0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  station::CycleLog& log = installation.OpenLog(site.history, unix0);
  for (const auto& n : log.notes()) fmt::print(stderr, "note: {}\n", n);
  runtime::LoopRunner runner(*comp, link, installation.temperatures(), runtime::LoopOptions{c.period_s, c.temperature_period_s},
                             &log.recorder());
  if (m.advance) runner.SetPlantAdvance(m.advance);

  std::unique_ptr<web::RunBackend> web_backend;
  cli::WebFrontEnd web_front_end;
  cli::WebCliOptions web_options = o.web;  // the command line over the config's [web]
  for (auto [cli_value, config_value] : {std::pair{&web_options.listen, &site.web.listen}, {&web_options.users, &site.web.users},
                                         {&web_options.cert, &site.web.cert}, {&web_options.key, &site.web.key}})
    if (cli_value->empty()) *cli_value = *config_value;
  if (!web_options.listen.empty()) {
    web::RunBackendOptions wo;
    wo.machine_id = o.machine_id_given || site.web.machine_id.empty() ? o.machine_id : site.web.machine_id;
    wo.machine_name = fs::path(site.virtual_machine.machine_file).stem().string();
    if (site.machine != station::MachineKind::kVirtual || wo.machine_name.empty()) wo.machine_name = o.machine_id;
    // The page reads a SQLite history; a PostgreSQL history is read with psql or `history` tools.
    if (store::IsPostgresUrl(site.history.db))
      fmt::print(stderr, "warning: the web page's history and export read a SQLite history only; {} is not shown there\n",
                 log.writer() ? log.writer()->path() : std::string("the PostgreSQL history"));
    else
      wo.history_db = site.history.db;
    wo.iso_dir = o.iso_dir == "auto" ? (fs::path(c.model_file).parent_path() / "day").string() : o.iso_dir;
    wo.unix0 = unix0;
    web_backend = std::make_unique<web::RunBackend>(*comp, &link, log.writer(), wo);
    web::RunBackend* backend = web_backend.get();
    log.Watch({[backend](const runtime::CycleRecord& r) { backend->OnRecord(r); },
               [backend](const station::PublishedModel& model, const std::string& sha, const std::string& label,
                         double unix_s) { backend->OnModelPublished(model, sha, label, unix_s); }});
    web_front_end = cli::StartWebFrontEnd(web_options, *web_backend);
  }

  g_stop = false;
  std::signal(SIGINT, RunCommandOnStopSignal);
  std::signal(SIGTERM, RunCommandOnStopSignal);
  if (!o.quiet)
    fmt::print(stderr, "trueaxis run: {} | model {} | cycle {} ms | {}\n", m.description, c.model_file, c.period_s * 1000,
               c.duration_s > 0 ? fmt::format("for {} s", c.duration_s) : std::string("until SIGINT/SIGTERM"));
  runner.Start();
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto next_status = t0 + std::chrono::duration<double>(o.status_interval_s);
  auto next_housekeeping = t0;
  std::vector<std::string> axis_names;
  for (const auto& a : comp->axes()) axis_names.push_back(a.axis);
  runtime::CycleRecord rec;
  std::string last_alarms;
  bool have_record = false;
  auto on_record = [&](const runtime::CycleRecord& r) {
    rec = r;
    have_record = true;
    std::string alarms = runtime::RecordAlarmNames(r, axis_names);  // "no_model_for_axis(Y)": which axis
    if (alarms != last_alarms && !o.quiet)
      fmt::print(stderr, "[{:.2f} s] alarms: {}\n", r.time_s, alarms.empty() ? "cleared" : alarms);
    last_alarms = std::move(alarms);
  };
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    log.Drain(on_record);
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - t0).count();
    if (now >= next_housekeeping) {
      next_housekeeping = now + std::chrono::seconds(1);
      comp->CollectRetired();
      log.Flush();  // at most a second of CSV rows lost to a kill -9
      if (c.model_reload) {
        try {
          if (installation.ReloadIfChanged() && !o.quiet)
            fmt::print(stderr, "[{:.2f} s] model reloaded from {} (ramping to it)\n", elapsed, c.model_file);
        } catch (const std::exception& e) {
          fmt::print(stderr, "[{:.2f} s] model NOT reloaded, keeping the running one: {}\n", elapsed, e.what());
        }
      }
    }
    if (!o.quiet && now >= next_status && have_record) {
      next_status = now + std::chrono::duration<double>(o.status_interval_s);
      std::string line = fmt::format("[{:.1f} s] {} |", elapsed, runner.Stats().BriefReport());
      for (std::size_t i = 0; i < rec.axis_count; ++i)
        line += fmt::format(" {} {:.3f} mm → {:+.1f} µm", axis_names[i], rec.axes[i].cnc_position_mm, rec.axes[i].output_um);
      fmt::print(stderr, "{}\n", line);
    }
    if (c.duration_s > 0 && elapsed >= c.duration_s) break;
  }
  if (web_front_end.server) web_front_end.server->Stop();
  runner.Stop();
  m.Close();
  log.Drain(on_record);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  log.Close();
  const auto stats = runner.Stats();
  fmt::print("{}\n", stats.BriefReport());
  if (log.Dropped()) fmt::print("log records dropped (consumer too slow): {}\n", log.Dropped());
  if (const store::HistoryWriter* writer = log.writer())  // path(): a URL without its password
    fmt::print("history: {} ({})\n", writer->path(), writer->Stats().BriefReport());
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "Run the real-time compensator against a configured machine (virtual or MODBUS TCP)");
  cmd->add_option("--config", opts->config, "Run configuration (TOML, docs/runtime.md)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--duration-s", opts->duration_s,
                  "Stop after this many seconds (0: until SIGINT/SIGTERM; default: the config's duration_s)")
      ->each([opts](const std::string&) { opts->duration_given = true; });
  cmd->add_option("--status-interval-s", opts->status_interval_s, "Seconds between status lines on stderr")
      ->capture_default_str();
  // The earlier spelling, still accepted (scripts written for it keep working); not shown in --help.
  cmd->add_option("--status-s", opts->status_interval_s, "Same as --status-interval-s")->group("");
  cmd->add_flag("--quiet", opts->quiet, "No progress on stderr");
  cli::AddWebOptions(cmd, opts->web, "--web");
  cmd->add_option("--machine-id", opts->machine_id, "The machine's id on the web page ([A-Za-z0-9_.-])")
      ->capture_default_str()
      ->each([opts](const std::string&) { opts->machine_id_given = true; });
  cmd->add_option("--web-iso-dir", opts->iso_dir,
                  "Laser tests <stem>_off.csv/<stem>_on.csv for the page's ISO 230-2 figures (auto: <model folder>/day)")
      ->capture_default_str();
  cmd->callback([opts] { Run(*opts); });
}

trueaxis::cli::CommandRegistrar reg("run", Setup);

}  // namespace
