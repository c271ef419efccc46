// trueaxis-hal --config RUN.toml [--name trueaxis] [--temperatures modbus|hal] [--campaign DIR]
// A LinuxCNC userspace HAL component: the real-time compensator of `trueaxis run` (the same
// runtime::Step, limiter, fault policies and model file) with LinuxCNC as the CNC — positions,
// velocities, coolant and an enable from HAL pins, the correction out to the axes' external
// offsets (axis.L.eoffset-counts) — and the temperatures from the terminal's RTD modules over
// MODBUS TCP ([machine] of the run config) or from HAL pins; its history and CSV log ([history])
// and model reload ([model] reload) as `run`'s. Load it from a HAL file:
//   loadusr -W trueaxis-hal --config /etc/trueaxis/run.toml
// Pins, INI and HAL snippets: docs/linuxcnc.md. Stops on SIGTERM (halcmd unloadusr) / SIGINT:
// the correction first ramps to zero through the limiter, then the component leaves HAL.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <memory>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "hal_campaign_log.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/linuxcnc/hal_cnc_link.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/linuxcnc/hal_temperatures.hpp"
#include "trueaxis/linuxcnc/status_pins.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/cycle_log.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/station/machine_connection.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop{false};
extern "C" void OnStopSignal(int) { g_stop.store(true); }

struct Options {
  std::string config;
  std::string name = "trueaxis";
  std::string temperatures = "modbus";
  double ramp_out_s = 10;  // longest wait for the correction to ramp to zero at stop
};

// The loop's cycles to the status pins and to the installation's record.
class StatusAndRecord : public runtime::CycleObserver {
 public:
  StatusAndRecord(runtime::CycleObserver& status, runtime::CycleObserver& record) : status_(status), record_(record) {}
  void OnCycle(const runtime::CycleStatus& s) override {
    status_.OnCycle(s);
    record_.OnCycle(s);
  }

 private:
  runtime::CycleObserver& status_;
  runtime::CycleObserver& record_;
};

// The axes LinuxCNC has ([machine] axes), each with its interface from [[axis]] (δ = eoffset count).
std::vector<runtime::AxisInterface> AxisInterfaces(const station::SiteConfig& site) {
  const station::InstallationConfig& c = site.installation;
  std::vector<runtime::AxisInterface> out;
  for (const auto& name : site.modbus.axis_names) {
    runtime::AxisInterface it;
    it.axis = name;
    for (const auto& a : c.axes)
      if (a.axis == name) it = a;
    out.push_back(it);
  }
  for (const auto& a : c.axes) {
    bool found = false;
    for (const auto& it : out) found = found || it.axis == a.axis;
    if (!found) throw InputError(c.source, 0, "axis.name", fmt::format("'{}' is not in [machine] axes", a.axis));
  }
  return out;
}

int Run(const Options& o) {
  const station::SiteConfig site = station::ReadSiteConfig(o.config);
  const station::InstallationConfig& c = site.installation;
  if (site.machine != station::MachineKind::kModbus)
    throw InputError(c.source, 0, "machine.kind",
                     "trueaxis-hal needs kind = \"modbus\": [machine] axes are the LinuxCNC axes, channels the "
                     "temperature channels (RTD modules at host:port, or HAL pins with --temperatures hal)");

  if (!site.web.listen.empty())
    fmt::print(stderr,
               "trueaxis-hal: warning: {}:{}: [web] listen = \"{}\" is ignored: trueaxis-hal serves no web page; "
               "read its [history] with `trueaxis history` (docs/linuxcnc.md)\n",
               site.source(), site.LineOf("web.listen"), site.web.listen);

  linuxcnc::HalComponent hal(o.name);
  linuxcnc::HalCncLink link(hal, AxisInterfaces(site));
  linuxcnc::HalTemperatures temperatures = linuxcnc::OpenHalTemperatures(hal, site, o.temperatures == "hal");
  hw::TemperatureSource* source = temperatures.source;
  std::vector<std::string> axis_names;
  for (std::size_t i = 0; i < link.AxisCount(); ++i) axis_names.push_back(link.AxisName(i));
  linuxcnc::StatusPins status(hal, axis_names);

  // The installation, as in `trueaxis run`: the one temperature pipeline ([signal]: calibration,
  // groups, max_disagreement_c), the compensator, the model (composite or thermal_channels).
  const auto t0_pipeline = std::chrono::steady_clock::now();
  station::Installation installation(
      c, link, *source, [t0_pipeline] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_pipeline).count(); },
      site.modbus.machine_name);
  for (const auto& w : installation.warnings()) fmt::print(stderr, "warning: {}\n", w);
  runtime::Compensator* comp = &installation.compensator();
  // Its record, as `run`'s: [history] database and CSV log, the model loaded and reloaded. The
  // loop's time 0 is its construction (its records' times stay Unix times across the enable wait);
  // a [history] the machine cannot open stops the component before LinuxCNC goes on.
  const double unix0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  station::CycleLog& log = installation.OpenLog(site.history, unix0);
  for (const auto& n : log.notes()) fmt::print(stderr, "trueaxis-hal: note: {}\n", n);
  StatusAndRecord observer(status, log.recorder());
  runtime::LoopRunner runner(*comp, link, installation.temperatures(), runtime::LoopOptions{c.period_s, c.temperature_period_s},
                             &observer);

  g_stop = false;
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  hal.Ready();  // every pin exists: `loadusr -W` returns, the HAL file nets them
  // The loop starts at the first C.enable with C.machine-on (the machine is on and its pins
  // carry values), so it never conditions the zeros of pins not yet driven.
  while (!g_stop.load() && !link.CncEnable()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (g_stop.load()) return 0;  // stopped before the first enable
  runner.Start();
  fmt::print(stderr, "trueaxis-hal: component {} | {} axes | temperatures {} | model {} | cycle {} ms\n", o.name,
             axis_names.size(), o.temperatures == "hal" ? "from HAL pins" : fmt::format("MODBUS {}:{}", site.modbus.host, site.modbus.port),
             c.model_file, c.period_s * 1000);
  std::string last_alarms;
  std::vector<std::uint32_t> axis_alarms(axis_names.size());
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto next_housekeeping = t0 + std::chrono::seconds(1);
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const runtime::CycleStatus& st = comp->LastStatus();  // a racy read for the log line only
    for (std::size_t i = 0; i < axis_alarms.size() && i < st.axes.size(); ++i) axis_alarms[i] = st.axes[i].alarms;
    std::string alarms = runtime::AlarmNamesWithAxes(st.alarms, axis_alarms, axis_names);  // with the axis
    if (alarms != last_alarms) fmt::print(stderr, "[{:.1f} s] alarms: {}\n", elapsed(), alarms.empty() ? "cleared" : alarms);
    last_alarms = std::move(alarms);
    log.Drain();
    if (std::chrono::steady_clock::now() >= next_housekeeping) {
      next_housekeeping = std::chrono::steady_clock::now() + std::chrono::seconds(1);
      comp->CollectRetired();
      log.Flush();
      if (c.model_reload) {
        try {
          if (installation.ReloadIfChanged())
            fmt::print(stderr, "[{:.1f} s] model reloaded from {} (ramping to it)\n", elapsed(), c.model_file);
        } catch (const std::exception& e) {
          fmt::print(stderr, "[{:.1f} s] model NOT reloaded, keeping the running one: {}\n", elapsed(), e.what());
        }
      }
    }
    if (c.duration_s > 0 && elapsed() >= c.duration_s) break;
  }
  // Stop: ramp the correction out through the limiter (never a jump), then leave HAL.
  comp->SetEnabled(false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.ramp_out_s);
  while (std::chrono::steady_clock::now() < deadline) {
    bool zero = true;
    for (const auto& a : comp->LastStatus().axes) zero = zero && a.written_um == 0;
    if (zero) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  runner.Stop();
  link.ReleaseOffsets();
  log.Close();
  fmt::print(stderr, "trueaxis-hal: stopped ({})\n", runner.Stats().BriefReport());
  if (const store::HistoryWriter* writer = log.writer())
    fmt::print(stderr, "trueaxis-hal: history {} ({})\n", writer->path(), writer->Stats().BriefReport());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"trueaxis-hal: the trueaxis compensator as a LinuxCNC userspace HAL component (docs/linuxcnc.md)"};
  app.add_option("--config", o.config, "Run configuration (TOML, docs/runtime.md; [machine] kind = \"modbus\")")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--name", o.name, "HAL component name (pin prefix)")->capture_default_str();
  app.add_option("--temperatures", o.temperatures, "modbus: the RTD modules of [machine]; hal: pins NAME.temp.<channel>")
      ->check(CLI::IsMember({"modbus", "hal"}))
      ->capture_default_str();
  app.add_option("--ramp-out-s", o.ramp_out_s, "At stop, wait at most this long for the correction to ramp to zero")
      ->capture_default_str();
  station::CampaignLogOptions campaign;
  hal_app::AddCampaignOptions(app, campaign);
  CLI11_PARSE(app, argc, argv);
  try {
    if (!campaign.dir.empty()) return hal_app::RunHalCampaignLog(o.config, o.name, o.temperatures == "hal", campaign);
    return Run(o);
  } catch (const InputError& e) {
    fmt::print(stderr, "trueaxis-hal: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "trueaxis-hal: {}\n", e.what());
    return 1;
  }
}
