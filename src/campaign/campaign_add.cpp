#include "trueaxis/campaign/campaign_add.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/measure/measurement_file.hpp"
#include "trueaxis/campaign/campaign_folder.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::campaign {
namespace {

double Round(double v, int digits) {
  const double s = std::pow(10.0, digits);
  return std::round(v * s) / s;
}

// The log's value of column `k` at campaign time t: linear between the two rows around t; NaN when
// either is empty (the channel was flagged).
double LogValueAt(const measure::TemperatureLog& log, std::size_t k, double t) {
  const auto it = std::lower_bound(log.time_s.begin(), log.time_s.end(), t);
  const std::size_t hi = static_cast<std::size_t>(it - log.time_s.begin());
  if (hi < log.time_s.size() && log.time_s[hi] == t) return log.rows[hi][k];
  const std::size_t lo = hi - 1;
  const double a = log.rows[lo][k], b = log.rows[hi][k];
  const double f = (t - log.time_s[lo]) / (log.time_s[hi] - log.time_s[lo]);
  return a + f * (b - a);
}

}  // namespace

CampaignAddResult AddToCampaign(const CampaignAddOptions& o) {
  const auto& states = measure::CampaignStates();
  if (std::find(states.begin(), states.end(), o.state) == states.end())
    throw InputError("command line", 0, "--state",
                     fmt::format("'{}' is not one of cold, warm, cooldown, ambient, coolant, coolant_rest", o.state));
  if (!o.start.empty() && !o.end.empty())
    throw InputError("command line", 0, "--end", "give the test's --start or its --end, not both");
  if (o.axis.empty()) throw InputError("command line", 0, "--axis", "name the measured axis (X, Y, …)");
  CampaignFolder folder = OpenCampaignFolder(o.campaign_dir);
  const CampaignClock clock = folder.Clock();
  const std::string log_path = folder.TemperatureLogPath();
  if (!std::filesystem::exists(log_path))
    throw InputError(folder.ManifestPath(), 0, "temperature_log",
                     fmt::format("'{}' does not exist: start `trueaxis campaign log` before the first test", log_path));
  const measure::TemperatureLog log = measure::ReadTemperatureLog(log_path);

  measure::Measurement m = measure::ReadMeasurementFile(o.file);
  if (m.points.empty()) throw InputError(o.file, 0, "", "no measurement points");
  const std::string file_axis(Trim(m.Meta("axis").value_or("")));
  if (!file_axis.empty() && LowerAscii(file_axis) != LowerAscii(o.axis))
    throw InputError(o.file, m.MetaLine("axis"), "axis",
                     fmt::format("the file says axis '{}', the command line --axis {}", file_axis, o.axis));
  if (measure::CompensationActive(m).value_or(false))
    throw InputError(o.file, m.MetaLine("compensation"), "compensation",
                     "measured with the compensation on: a thermal model is fitted on tests with the compensation off");
  // Each point's time since the test's start: the laser software's time column.
  double duration_s = 0;
  for (const auto& p : m.points) {
    if (!p.time_s)
      throw InputError(o.file, p.source_line, "time_s",
                       "the point has no time: the temperatures at each point come from the log by the point's time "
                       "(export the laser run with its time column)");
    duration_s = std::max(duration_s, *p.time_s);
  }

  // The test's start on the campaign clock: the option, the file's date, or its modification time.
  CampaignAddResult r;
  double start_unix = 0;
  auto parse = [&](const std::string& text, const std::string& field, const std::string& where, int line) {
    const auto t = ParseCampaignDate(text);
    if (!t) throw InputError(where, line, field, fmt::format("'{}' is not a date like 2026-11-28T09:12:00", text));
    return *t;
  };
  double offset_s = 0;  // the file's times and dates are the test's start, unless given as its end
  if (!o.start.empty()) {
    start_unix = parse(o.start, "--start", "command line", 0);
    r.start_source = "--start";
  } else if (!o.end.empty()) {
    start_unix = parse(o.end, "--end", "command line", 0);
    offset_s = -duration_s;
    r.start_source = "--end";
  } else if (auto date = m.Meta("date"); date && ParseCampaignDate(*date)) {
    start_unix = *ParseCampaignDate(*date);
    r.start_source = fmt::format("the file's date (line {})", m.MetaLine("date"));
  } else {
    if (date)
      throw InputError(o.file, m.MetaLine("date"), "date",
                       fmt::format("'{}' is not a date with a time of day; give the test's --start", *date));
    // Laser software writes the file when the test ends.
    const auto mtime = std::filesystem::last_write_time(o.file);
    const auto sys = std::chrono::file_clock::to_sys(mtime);
    start_unix = std::chrono::duration<double>(sys.time_since_epoch()).count();
    offset_s = -duration_s;
    r.start_source = "the file's modification time (taken as the test's end)";
  }
  // Times inside the file are the machine's own seconds; a date is wall time (CampaignClock).
  const double start_s = clock.FromUnix(start_unix) + offset_s;
  const double end_s = start_s + duration_s;
  r.start_time_s = start_s;
  r.end_time_s = end_s;
  r.start_date = FormatCampaignDate(clock.start_unix_s + start_s / clock.scale);

  // The log must cover the whole test, without a hole (the logger stopped) inside it.
  if (start_s < log.time_s.front() || end_s > log.time_s.back())
    throw InputError(log_path, start_s < log.time_s.front() ? log.line.front() : log.line.back(), "time_s",
                     fmt::format("the log covers {:.0f}–{:.0f} s of the campaign clock, but {} runs {:.0f}–{:.0f} s "
                                 "(start {} from {}): {}",
                                 log.time_s.front(), log.time_s.back(), o.file, start_s, end_s, r.start_date,
                                 r.start_source,
                                 end_s > log.time_s.back() ? "add it once the log has passed its end"
                                                           : "the log was not running then"));
  double period_s = 0;
  {
    std::vector<double> steps;
    for (std::size_t i = 1; i < log.time_s.size(); ++i) steps.push_back(log.time_s[i] - log.time_s[i - 1]);
    std::sort(steps.begin(), steps.end());
    period_s = steps.empty() ? 0 : steps[steps.size() / 2];
  }
  // A hole of more than three rows and ten minutes: the logger was stopped (temperatures drift by
  // far less than a test's resolution over a shorter one, and it tolerates a stalled computer).
  const double max_gap_s = std::max(3 * period_s + 1, 600.0);
  for (std::size_t i = 1; i < log.time_s.size(); ++i)
    if (log.time_s[i] > start_s && log.time_s[i - 1] < end_s && log.time_s[i] - log.time_s[i - 1] > max_gap_s)
      throw InputError(log_path, log.line[i], "time_s",
                       fmt::format("the log has a gap from {:.0f} to {:.0f} s during {} ({:.0f}–{:.0f} s): the "
                                   "temperatures of its points are not known",
                                   log.time_s[i - 1], log.time_s[i], o.file, start_s, end_s));

  // Every logged temperature at every point's time; the file's own columns the log lacks are kept.
  std::vector<std::string> names = log.sensors;
  std::vector<int> keep;  // the file's columns kept
  for (std::size_t k = 0; k < m.sensor_names.size(); ++k)
    if (std::find(names.begin(), names.end(), m.sensor_names[k]) == names.end()) {
      keep.push_back(static_cast<int>(k));
      names.push_back(m.sensor_names[k]);
    }
  for (auto& p : m.points) {
    std::vector<double> temps;
    const double t = start_s + *p.time_s;
    for (std::size_t k = 0; k < log.sensors.size(); ++k) temps.push_back(LogValueAt(log, k, t));
    for (int k : keep) temps.push_back(p.temperatures_c[static_cast<std::size_t>(k)]);
    p.temperatures_c = std::move(temps);
  }
  m.sensor_names = names;

  // The coolant: the option, else what the log says during the test.
  std::string coolant = o.coolant;
  if (coolant.empty()) {
    coolant = "off";
    if (!log.coolant.empty()) {
      std::map<CoolantState, int> seen;
      for (std::size_t i = 0; i < log.time_s.size(); ++i)
        if (log.time_s[i] >= start_s - period_s && log.time_s[i] <= end_s + period_s) ++seen[log.coolant[i]];
      int best = 0;
      for (const auto& [state, n] : seen)
        if (n > best) best = n, coolant = CoolantStateName(state);
    }
  }
  if (!ParseCoolantState(coolant))
    throw InputError("command line", 0, "--coolant", fmt::format("'{}' is not one of off, flood, mist, air", coolant));
  if ((o.state == "coolant" || o.state == "coolant_rest") && coolant == "off")
    throw InputError("command line", 0, "--coolant",
                     fmt::format("state {} needs a coolant, but the log reads coolant off during the test; give --coolant "
                                 "flood (or mist/air)", o.state));

  // Sequence and file name as the virtual machine's campaign names them.
  auto& list = folder.Measurements();
  const std::string axis = o.axis;
  int sequence = 1, axis_files = 1;
  double cold_nut = std::numeric_limits<double>::quiet_NaN();
  const std::string nut = LowerAscii(axis) + "_nut";
  for (const auto& e : list) {
    if (!e.is_object() || !e.contains("axis") || !e["axis"].is_string() || e["axis"].get<std::string>() != axis) continue;
    ++axis_files;
    if (e.value("state", std::string()) == o.state) ++sequence;
    if (e.value("state", std::string()) == "cold" && e.contains("mean_temperatures_c") &&
        e["mean_temperatures_c"].contains(nut) && e["mean_temperatures_c"][nut].is_number())
      cold_nut = e["mean_temperatures_c"][nut].get<double>();
  }
  const std::string name = fmt::format("{}_{:02}_{}{}.csv", axis, axis_files, o.state,
                                       o.state == "cold" ? std::string() : fmt::format("_{:02}", sequence));
  const std::filesystem::path out = std::filesystem::path(o.campaign_dir) / name;
  if (std::filesystem::exists(out))
    throw InputError(out.string(), 0, "", "already exists but manifest.json does not list it: remove it or restore the manifest");

  std::map<std::string, double> means;
  for (std::size_t k = 0; k < m.sensor_names.size(); ++k) {
    double sum = 0;
    int n = 0;
    for (const auto& p : m.points)
      if (std::isfinite(p.temperatures_c[k])) sum += p.temperatures_c[k], ++n;
    means[m.sensor_names[k]] = n ? sum / n : std::numeric_limits<double>::quiet_NaN();
  }
  if (o.state == "cold") cold_nut = means.count(nut) ? means[nut] : cold_nut;
  r.nut_rise_c = means.count(nut) ? means[nut] - cold_nut : std::numeric_limits<double>::quiet_NaN();
  r.sequence = sequence;

  m.SetMeta("axis", axis);
  m.SetMeta("state", o.state);
  m.SetMeta("sequence", std::to_string(sequence));
  m.SetMeta("coolant", coolant);
  m.SetMeta("date", r.start_date);
  m.SetMeta("campaign_time_s", FormatShortest(Round(start_s, 1)));
  m.SetMeta("duration_s", FormatShortest(Round(duration_s, 1)));
  if (std::isfinite(r.nut_rise_c)) m.SetMeta("nut_rise_c", FormatShortest(Round(r.nut_rise_c, 3)));
  m.SetMeta("laser_file", std::filesystem::path(o.file).filename().string());
  m.SetMeta("start_from", r.start_source);
  // The soak the fit's ρ takes (docs/real-machine.md): the machine file's CTE via the plan, unless
  // the laser file gives its own.
  if (!m.Meta("cte_um_per_m_c"))
    if (const auto cte = folder.PlannedCteUmPerMC(axis)) m.SetMeta("cte_um_per_m_c", FormatShortest(*cte));
  measure::WriteMeasurementCsv(m, out.string());

  nlohmann::ordered_json e;
  e["file"] = name;
  e["axis"] = axis;
  e["state"] = o.state;
  e["coolant"] = coolant;
  e["sequence"] = sequence;
  e["start_date"] = r.start_date;
  e["start_time_s"] = Round(start_s, 1);
  e["end_time_s"] = Round(end_s, 1);
  if (std::isfinite(r.nut_rise_c)) e["nut_rise_c"] = Round(r.nut_rise_c, 3);
  e["laser_file"] = std::filesystem::path(o.file).filename().string();
  auto& mt = e["mean_temperatures_c"] = nlohmann::ordered_json::object();
  for (const auto& s : log.sensors) {
    const double v = means[s];
    if (std::isfinite(v)) mt[s] = Round(v, 3);
    else mt[s] = nullptr;
  }
  list.push_back(e);
  folder.Save();
  r.written = out.string();
  return r;
}

}  // namespace trueaxis::campaign
