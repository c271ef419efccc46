// The logging loop of `trueaxis campaign log` and `trueaxis-hal --campaign` (campaign_log_loop.hpp).
#include "trueaxis/station/campaign_log_loop.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/campaign/campaign_clock.hpp"
#include "trueaxis/campaign/campaign_folder.hpp"
#include "trueaxis/campaign/warmup_watch.hpp"
#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/station/campaign_logger.hpp"

namespace trueaxis::station {

std::size_t RunCampaignLog(const CampaignLogOptions& o, const CampaignLogChannels& ch, const std::atomic<bool>& stop) {
  if (!(o.period_s >= 1 && o.period_s <= 3600))
    throw InputError("command line", 0, "--period-s", fmt::format("{} is not in [1, 3600] s", o.period_s));
  if (!(o.clock_scale >= 0 && std::isfinite(o.clock_scale)))
    throw InputError("command line", 0, "--clock-scale", "must be a number > 0");
  if (!ch.source) throw std::invalid_argument("RunCampaignLog: no temperature source");
  std::vector<std::string> axes, sensors;
  if (ch.link)
    for (std::size_t a = 0; a < ch.link->AxisCount(); ++a) axes.push_back(ch.link->AxisName(a));
  for (std::size_t c = 0; c < ch.source->ChannelCount(); ++c) sensors.push_back(ch.source->ChannelName(c));
  for (const auto& a : o.axes)
    if (std::find(axes.begin(), axes.end(), a) == axes.end())
      throw InputError("command line", 0, "--axis", fmt::format("the machine has no axis '{}' ({})", a, fmt::join(axes, ", ")));

  // The campaign: its manifest (started here when no plan wrote one) and clock.
  std::filesystem::create_directories(o.dir);
  campaign::CampaignFolder folder;
  const double now0 = campaign::WallClockNowS();
  if (!std::filesystem::exists(std::filesystem::path(o.dir) / "manifest.json")) {
    folder = campaign::NewCampaignFolder(o.dir, std::floor(now0), sensors, o.clock_scale > 0 ? o.clock_scale : 1);
    folder.Save();
    fmt::print("started the campaign {} at {} (no manifest.json: campaign plan writes one with a plan)\n", o.dir,
               folder.manifest["start_date"].get<std::string>());
  } else {
    folder = campaign::OpenCampaignFolder(o.dir);
    bool changed = false;
    if (!folder.manifest.contains("start_date") || folder.manifest["start_date"].is_null() ||
        folder.manifest["start_date"] == "") {
      folder.manifest["start_date"] = campaign::FormatCampaignDate(std::floor(now0));
      changed = true;
    }
    if (o.clock_scale > 0 && !folder.manifest.contains("clock_scale") && o.clock_scale != 1) {
      folder.manifest["clock_scale"] = o.clock_scale;
      changed = true;
    }
    if (changed) folder.Save();
  }
  const campaign::CampaignClock clock = folder.Clock();
  if (o.clock_scale > 0 && o.clock_scale != clock.scale)
    throw InputError(folder.ManifestPath(), 0, "clock_scale",
                     fmt::format("the campaign's clock runs at {} campaign seconds per wall second, --clock-scale says {}",
                                 clock.scale, o.clock_scale));
  const std::string log_path = folder.TemperatureLogPath();
  station::CampaignLogger logger(log_path, axes, sensors);

  // The warm-up watch's history: the log so far, then every row written.
  std::vector<double> times, travel_sum;
  std::vector<std::vector<double>> nut(axes.size());
  std::vector<int> nut_channel(axes.size(), -1);
  for (std::size_t a = 0; a < axes.size(); ++a)
    for (std::size_t c = 0; c < sensors.size(); ++c)
      if (sensors[c] == LowerAscii(axes[a]) + "_nut") nut_channel[a] = static_cast<int>(c);
  if (logger.ResumedRows() > 0) {
    const auto log = measure::ReadTemperatureLog(log_path);
    for (std::size_t r = 0; r < log.time_s.size(); ++r) {
      times.push_back(log.time_s[r]);
      double sum = 0;
      for (const auto& [axis, series] : log.travel_mm) sum += std::isfinite(series[r]) ? series[r] : 0;
      travel_sum.push_back(sum);
      for (std::size_t a = 0; a < axes.size(); ++a) nut[a].push_back(nut_channel[a] >= 0 ? log.rows[r][nut_channel[a]] : NAN);
    }
    fmt::print("continuing {} after its {} rows (last at {:.1f} s of the campaign clock)\n", log_path, logger.ResumedRows(),
               logger.LastTimeS());
  }
  std::vector<std::string> watched = o.axes;
  if (watched.empty())
    for (std::size_t a = 0; a < axes.size(); ++a)
      if (nut_channel[a] >= 0) watched.push_back(axes[a]);
  fmt::print("logging {} ({} axes, {} temperature channels) every {} s into {}; stop with Ctrl-C{}\n", ch.description,
             axes.size(), sensors.size(), o.period_s, log_path,
             o.duration_s > 0 ? fmt::format(" (or after {} s)", o.duration_s) : std::string());
  std::fflush(stdout);

  const bool live = o.status || isatty(STDOUT_FILENO);
  sim::WarmUpRule rule;
  rule.max_measurements = o.max_warm;
  std::vector<hw::AxisState> axis_state(axes.size());
  std::vector<hw::RawTemperature> temps(sensors.size());
  std::string last_events;
  const double period_wall_s = o.period_s / clock.scale;
  const double poll_wall_s = std::clamp(period_wall_s / 10, 0.005, 0.1);
  const auto t0 = std::chrono::steady_clock::now();
  auto last = t0;
  double next_row_s = std::isfinite(logger.LastTimeS()) ? logger.LastTimeS() + o.period_s : clock.FromUnix(now0);
  while (!stop.load()) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - t0).count();
    if (o.duration_s > 0 && elapsed >= o.duration_s) break;
    if (ch.advance) ch.advance(std::chrono::duration<double>(now - last).count());
    last = now;
    hw::CncState cnc;
    const bool cnc_ok = ch.link && ch.link->Read(axis_state, cnc);
    if (cnc_ok) logger.Poll(axis_state);
    const double t = clock.FromUnix(campaign::WallClockNowS());
    if (t >= next_row_s) {
      const bool temps_ok = ch.source->Read(temps);
      const std::string date = campaign::FormatCampaignDate(clock.start_unix_s + t / clock.scale);
      if (logger.Append(t, date, cnc_ok ? std::optional<hw::CncState>(cnc) : std::nullopt,
                        temps_ok ? std::optional<std::span<const hw::RawTemperature>>(temps) : std::nullopt)) {
        times.push_back(logger.LastTimeS());
        double sum = 0;
        for (double v : logger.TravelMm()) sum += v;
        travel_sum.push_back(sum);
        for (std::size_t a = 0; a < axes.size(); ++a)
          nut[a].push_back(nut_channel[a] >= 0 && temps_ok && !temps[nut_channel[a]].hardware_fault ? temps[nut_channel[a]].temp_c
                                                                                                     : NAN);
        // The warm-up: the manifest as `campaign add` left it, the nut as logged.
        std::string line, events;
        try {
          const auto manifest = campaign::OpenCampaignFolder(o.dir).manifest;
          const auto& list = manifest.contains("measurements") ? manifest["measurements"] : nlohmann::ordered_json::array();
          for (const auto& axis : watched) {
            const std::size_t a = static_cast<std::size_t>(std::find(axes.begin(), axes.end(), axis) - axes.begin());
            const auto st = campaign::WatchWarmUp(rule, o.warmup_per_test, list, axis, times, nut[a], travel_sum, o.period_s);
            line += (line.empty() ? "" : " | ") + st.Text();
            if (st.due || st.saturated) events += (events.empty() ? "" : " | ") + st.Text();
          }
        } catch (const InputError& e) {
          line = fmt::format("manifest: {}", e.what());
        }
        const std::string stamp = fmt::format("[{} t={:.2f} h]", date, logger.LastTimeS() / 3600);
        if (live) fmt::print("{} {}\n", stamp, line);
        else if (!events.empty() && events != last_events) fmt::print("{} {}\n", stamp, events);
        last_events = events;
        std::fflush(stdout);
      }
      // Rows are due on the campaign's clock (a virtual machine's may run faster than the wall),
      // not the steady clock: so this loop polls the clock instead of being a core::PeriodicThread.
      next_row_s += o.period_s;
      if (next_row_s <= t) next_row_s = t + o.period_s;  // a stall (suspended laptop): no burst of rows
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_wall_s));
  }
  fmt::print("stopped: {} rows appended to {}\n", logger.AppendedRows(), log_path);
  return logger.AppendedRows();
}

}  // namespace trueaxis::station
