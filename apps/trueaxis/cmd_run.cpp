// trueaxis run --config FILE.toml [--duration-s S] [--quiet] [--web HOST:PORT --users FILE]
// Runs the real-time compensator against the configured machine — the
// virtual machine in process, or a CNC terminal and RTD modules over MODBUS
// TCP — until SIGINT/SIGTERM or the duration, logging to the history
// database and/or a CSV file (docs/runtime.md). With --web, the machine is also served to the
// browser behind a login (docs/web.md).
#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/station/history_logger.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/runtime/run_config.hpp"
#include "trueaxis/station/machine_connection.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/station/model_loading.hpp"
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

// A decimated CSV log of the loop: time, alarms, per axis position/correction, per channel value.
// A run appends to the log of earlier runs (never overwrites it); a last row cut short by a
// kill -9 is removed first, and a log with other columns is refused rather than mixed.
class CsvLog {
 public:
  CsvLog(const std::string& path, const runtime::Compensator& comp) {
    for (const auto& a : comp.axes()) axis_names_.push_back(a.axis);
    std::string header = "time_s,alarms";
    for (const auto& a : comp.axes()) header += "," + a.axis + "_position_mm," + a.axis + "_correction_um";
    for (const auto& ch : comp.channel_names()) header += ",t_" + ch + "_c";
    std::error_code ec;
    const bool existing = fs::exists(path, ec) && fs::file_size(path, ec) > 0;
    if (existing) {
      const std::string text = ReadTextFile(path);
      const std::string first = text.substr(0, text.find('\n'));
      if (first != header)
        throw InputError(path, 1, "header",
                         "the log has other columns (written by another configuration): move it away or name "
                         "another [history] csv");
      const auto last_newline = text.rfind('\n');
      if (last_newline + 1 != text.size()) {
        fs::resize_file(path, last_newline + 1);  // drop the row a kill -9 cut short
        repaired_ = true;
      }
    }
    out_.open(path, std::ios::app);
    if (!out_) throw InputError(path, 0, "history.csv", "cannot open for writing");
    if (!existing) out_ << header << "\n";
  }
  bool repaired() const { return repaired_; }
  void Write(const runtime::CycleRecord& r) {
    out_ << fmt::format("{:.3f},{}", r.time_s, runtime::RecordAlarmNames(r, axis_names_));
    for (std::size_t i = 0; i < r.axis_count; ++i)
      out_ << fmt::format(",{:.4f},{:.3f}", r.axes[i].cnc_position_mm, r.axes[i].output_um);
    for (std::size_t i = 0; i < r.channel_count; ++i) out_ << fmt::format(",{:.3f}", r.temp_c[i]);
    out_ << "\n";
  }
  void Flush() { out_.flush(); }

 private:
  std::ofstream out_;
  std::vector<std::string> axis_names_;
  bool repaired_ = false;
};

void Run(const Options& o) {
  if (o.duration_given) cli::CheckSecondsOption(o.duration_s, "--duration-s", "until SIGINT/SIGTERM");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "every 50 ms");
  runtime::RunConfig c = runtime::ReadRunConfig(o.config);
  if (o.duration_given) c.duration_s = o.duration_s;
  station::Machine m = station::OpenMachine(c, /*with_pipeline=*/false);  // the hardware
  for (const auto& w : m.warnings) fmt::print(stderr, "warning: {}\n", w);
  // The coolant state the compensator sees can be forced from the web page.
  web::CoolantOverrideLink link(*m.link);
  // The installation: the temperature pipeline ([signal], on by default), the compensator and the
  // model — InputError (exit 2) on a model that does not fit the machine.
  station::Installation installation(c, link, *m.source, m.Clock(), m.name);
  for (const auto& w : installation.warnings()) fmt::print(stderr, "warning: {}\n", w);
  runtime::Compensator* comp = &installation.compensator();
  const station::PublishedModel first_model = installation.model();
  const std::string& first_revision = first_model.revision;

  const auto every = static_cast<std::uint64_t>(std::max(1.0, std::round(c.record_interval_s / c.period_s)));
  runtime::CycleRecorder recorder(8192, every);
  runtime::LoopRunner runner(*comp, link, installation.temperatures(), runtime::LoopOptions{c.period_s, c.temperature_period_s}, &recorder);
  if (m.advance) runner.SetPlantAdvance(m.advance);

  const double unix0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  std::unique_ptr<store::HistoryWriter> writer;
  std::unique_ptr<station::HistoryLogger> history;
  std::vector<std::string> axis_names;
  for (const auto& a : comp->axes()) axis_names.push_back(a.axis);
  if (!c.history_db.empty()) {
    if (!store::IsPostgresUrl(c.history_db) && fs::path(c.history_db).has_parent_path())
      fs::create_directories(fs::path(c.history_db).parent_path());
    writer = std::make_unique<store::HistoryWriter>(store::OpenHistorySink(c.history_db));
    history = std::make_unique<station::HistoryLogger>(*writer, axis_names, comp->channel_names(), unix0);
    history->LogModelChange(0, model::Sha256OfFile(c.model_file), first_revision, "loaded " + c.model_file);
  }
  std::unique_ptr<web::RunBackend> web_backend;
  cli::WebFrontEnd web_front_end;
  cli::WebCliOptions web_options = o.web;  // the command line over the config's [web]
  for (auto [cli_value, config_value] : {std::pair{&web_options.listen, &c.web.listen}, {&web_options.users, &c.web.users},
                                         {&web_options.cert, &c.web.cert}, {&web_options.key, &c.web.key}})
    if (cli_value->empty()) *cli_value = *config_value;
  if (!web_options.listen.empty()) {
    web::RunBackendOptions wo;
    wo.machine_id = o.machine_id_given || c.web.machine_id.empty() ? o.machine_id : c.web.machine_id;
    wo.machine_name = fs::path(c.virtual_machine.machine_file).stem().string();
    if (c.machine != runtime::MachineKind::kVirtual || wo.machine_name.empty()) wo.machine_name = o.machine_id;
    // The page reads a SQLite history; a PostgreSQL history is read with psql or `history` tools.
    if (store::IsPostgresUrl(c.history_db))
      fmt::print(stderr, "warning: the web page's history and export read a SQLite history only; {} is not shown there\n",
                 writer ? writer->path() : std::string("the PostgreSQL history"));
    else
      wo.history_db = c.history_db;
    wo.iso_dir = o.iso_dir == "auto" ? (fs::path(c.model_file).parent_path() / "day").string() : o.iso_dir;
    wo.unix0 = unix0;
    web_backend = std::make_unique<web::RunBackend>(*comp, &link, writer.get(), wo);
    web_backend->OnModelPublished(first_model, model::Sha256OfFile(c.model_file), c.model_file, unix0);
    web_front_end = cli::StartWebFrontEnd(web_options, *web_backend);
  }
  std::unique_ptr<CsvLog> csv;
  if (!c.log_csv.empty()) {
    if (fs::path(c.log_csv).has_parent_path()) fs::create_directories(fs::path(c.log_csv).parent_path());
    csv = std::make_unique<CsvLog>(c.log_csv, *comp);
    if (csv->repaired())
      fmt::print(stderr, "note: {}: its last row was cut short (the previous run was killed); removed, appending\n",
                 c.log_csv);
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
  runtime::CycleRecord rec;
  std::string last_alarms;
  bool have_record = false;
  auto drain = [&] {
    while (recorder.Pop(rec)) {
      have_record = true;
      if (history) history->Log(rec);
      if (web_backend) web_backend->OnRecord(rec);
      if (csv) csv->Write(rec);
      std::string alarms = runtime::RecordAlarmNames(rec, axis_names);  // "no_model_for_axis(Y)": which axis
      if (alarms != last_alarms && !o.quiet)
        fmt::print(stderr, "[{:.2f} s] alarms: {}\n", rec.time_s, alarms.empty() ? "cleared" : alarms);
      last_alarms = std::move(alarms);
    }
  };
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    drain();
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - t0).count();
    if (now >= next_housekeeping) {
      next_housekeeping = now + std::chrono::seconds(1);
      comp->CollectRetired();
      if (csv) csv->Flush();  // at most a second of rows lost to a kill -9
      if (c.model_reload) {
        try {
          if (const auto next = installation.ReloadIfChanged()) {
            if (web_backend)
              web_backend->OnModelPublished(*next, model::Sha256OfFile(c.model_file), "reloaded " + c.model_file,
                                            unix0 + elapsed);
            if (history)
              history->LogModelChange(elapsed, model::Sha256OfFile(c.model_file), next->revision, "reloaded " + c.model_file);
            if (!o.quiet) fmt::print(stderr, "[{:.2f} s] model reloaded from {} (ramping to it)\n", elapsed, c.model_file);
          }
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
  drain();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (csv) csv->Flush();
  const auto stats = runner.Stats();
  fmt::print("{}\n", stats.BriefReport());
  if (recorder.Dropped()) fmt::print("log records dropped (consumer too slow): {}\n", recorder.Dropped());
  if (writer) {
    writer->Close();
    fmt::print("history: {} ({})\n", writer->path(), writer->Stats().BriefReport());  // path(): a URL without its password
  }
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
