// trueaxis-hal --campaign DIR (hal_campaign_log.hpp).
#include "hal_campaign_log.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <limits>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/linuxcnc/hal_cnc_link.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/linuxcnc/hal_temperature_source.hpp"
#include "trueaxis/linuxcnc/hal_temperatures.hpp"
#include "trueaxis/station/site_config.hpp"

namespace trueaxis::hal_app {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void OnCampaignStopSignal(int) { g_stop.store(true); }

// LinuxCNC's axes for the log: HalCncLink's pins, the travelled path counted from pos-fb only while
// the machine is on (motion.motion-enabled) in two successive reads. An axis moves only then, and
// the pins read 0 until the HAL file has netted them: that first jump is no travel.
class CampaignHalLink : public hw::CncLink {
 public:
  explicit CampaignHalLink(linuxcnc::HalCncLink& link)
      : link_(link), travel_mm_(link.AxisCount(), 0.0),
        last_mm_(link.AxisCount(), std::numeric_limits<double>::quiet_NaN()) {}
  std::size_t AxisCount() const override { return link_.AxisCount(); }
  std::string AxisName(std::size_t axis) const override { return link_.AxisName(axis); }
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override {
    if (!link_.Read(axes, machine)) return false;
    const bool on = link_.MachineOn();
    for (std::size_t a = 0; a < axes.size() && a < travel_mm_.size(); ++a) {
      const double p = axes[a].position_mm;
      if (on && was_on_ && std::isfinite(last_mm_[a])) travel_mm_[a] += std::abs(p - last_mm_[a]);
      last_mm_[a] = p;
      axes[a].travel_mm = travel_mm_[a];  // the counter the campaign logger continues
    }
    was_on_ = on;
    return true;
  }
  bool WriteCompensation(std::span<const double>) override { return false; }  // a logger corrects nothing

 private:
  linuxcnc::HalCncLink& link_;
  std::vector<double> travel_mm_, last_mm_;
  bool was_on_ = false;
};

}  // namespace

void AddCampaignOptions(CLI::App& app, station::CampaignLogOptions& o) {
  app.add_option("--campaign", o.dir,
                 "Log the campaign instead of compensating: every temperature and LinuxCNC's state into "
                 "DIR/temperature_log.csv, and when the next warm-up test is due (as `trueaxis campaign log`)");
  app.add_option("--campaign-period-s", o.period_s, "--campaign: seconds between two rows")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--campaign-duration-s", o.duration_s, "--campaign: stop after this many seconds (0: until unloaded)")
      ->capture_default_str();
  app.add_option("--campaign-axis", o.axes,
                 "--campaign: axes whose warm-up to watch (default: every axis with a <axis>_nut sensor)")
      ->delimiter(',');
  app.add_option("--max-warm", o.max_warm, "--campaign: at most this many warm-up tests per axis")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--warmup-per-test", o.warmup_per_test,
                 "--campaign: each warm-up test also waits for this many times the last test's duration of machining")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
}

int RunHalCampaignLog(const std::string& config_path, const std::string& name, bool temperatures_from_hal,
                      const station::CampaignLogOptions& options) {
  const station::SiteConfig c = station::ReadSiteConfig(config_path, /*model_required=*/false);
  if (c.machine != station::MachineKind::kModbus)
    throw InputError(c.source(), 0, "machine.kind",
                     "trueaxis-hal needs kind = \"modbus\": [machine] axes are the LinuxCNC axes, channels the "
                     "temperature channels");
  if (!(options.duration_s >= 0 && std::isfinite(options.duration_s)))
    throw InputError("command line", 0, "--campaign-duration-s", "must be 0 (until unloaded) or a number of seconds");
  std::vector<runtime::AxisInterface> axes;
  for (const auto& n : c.modbus.axis_names) axes.push_back(runtime::AxisInterface{.axis = n});
  linuxcnc::HalComponent hal(name);
  linuxcnc::HalCncLink pins(hal, axes);
  linuxcnc::HalTemperatures temperatures = linuxcnc::OpenHalTemperatures(hal, c, temperatures_from_hal);
  CampaignHalLink link(pins);
  auto* temperature_pins = dynamic_cast<linuxcnc::HalTemperatureSource*>(temperatures.own.get());
  g_stop = false;
  std::signal(SIGINT, OnCampaignStopSignal);
  std::signal(SIGTERM, OnCampaignStopSignal);
  hal.Ready();
  // The first row waits for the HAL file's nets: before them the pins read 0 (0 °C, X at 0), which
  // the log must never record as the machine's state. Positions, machine-on and the temperature
  // pins must be netted (a sensor left unconnected: net its pin, or leave it out of channels).
  const auto t0 = std::chrono::steady_clock::now();
  bool said = false;
  while (!g_stop.load()) {
    std::vector<std::string> missing = pins.StatePinsNotNetted();
    if (temperature_pins)
      for (auto& p : temperature_pins->PinsNotNetted()) missing.push_back(std::move(p));
    if (missing.empty()) break;
    if (!said && std::chrono::steady_clock::now() - t0 > std::chrono::seconds(5)) {
      fmt::print(stderr, "trueaxis-hal: the campaign log waits for these pins to be netted: {}\n", fmt::join(missing, ", "));
      said = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // LinuxCNC starts the HAL threads after its last HAL file: until then the netted pins still read
  // 0 (an analog input's value, joint.N.pos-fb). Give it that moment before the first row.
  const auto settle_until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!g_stop.load() && std::chrono::steady_clock::now() < settle_until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (g_stop.load()) return 0;
  station::CampaignLogChannels channels;
  channels.link = &link;
  channels.source = temperatures.source;
  channels.description = fmt::format("LinuxCNC through HAL (component {}, temperatures {})", name,
                                     temperatures_from_hal ? "from HAL pins"
                                                           : fmt::format("MODBUS {}:{}", c.modbus.host, c.modbus.port));
  station::RunCampaignLog(options, channels, g_stop);
  return 0;
}

}  // namespace trueaxis::hal_app
