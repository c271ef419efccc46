#include "trueaxis/campaign/campaign_check.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/measure/measurement_file.hpp"

namespace trueaxis::campaign {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool KeyLocation(const std::string& location, const std::string& axis) {
  const std::string p = LowerAscii(axis) + "_";
  if (location == "ambient" || location.rfind("bed", 0) == 0) return true;
  return location.rfind(p, 0) == 0;  // the axis's own nut, bearings, motor, structure
}

// The log's rows in [from, to]: their mean of `sensor` (NaN when none has a reading).
double LogMean(const measure::TemperatureLog& log, int sensor, double from, double to) {
  if (sensor < 0) return kNaN;
  double sum = 0;
  int n = 0;
  for (std::size_t r = 0; r < log.time_s.size(); ++r)
    if (log.time_s[r] >= from && log.time_s[r] <= to && std::isfinite(log.rows[r][static_cast<std::size_t>(sensor)])) {
      sum += log.rows[r][static_cast<std::size_t>(sensor)];
      ++n;
    }
  return n ? sum / n : kNaN;
}

// The largest interval between two log rows (the log's own step), at least a minute.
double LogStepS(const measure::TemperatureLog& log) {
  std::vector<double> steps;
  for (std::size_t r = 1; r < log.time_s.size(); ++r) steps.push_back(log.time_s[r] - log.time_s[r - 1]);
  if (steps.empty()) return 60;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return std::max(60.0, steps[steps.size() / 2]);
}

struct EntryFacts {
  const measure::CampaignEntry* entry = nullptr;
  double start_s = kNaN, end_s = kNaN;
  std::map<std::string, double> mean_c;  // per sensor: the manifest's, else the log's over the test, else the file's
};

double FileMean(const measure::Measurement& m, const std::string& sensor) {
  const auto i = m.SensorIndex(sensor);
  if (!i) return kNaN;
  double sum = 0;
  int n = 0;
  for (const auto& p : m.points)
    if (std::isfinite(p.temperatures_c[*i])) sum += p.temperatures_c[*i], ++n;
  return n ? sum / n : kNaN;
}

// Seconds from midnight to the campaign clock's zero (the manifest's start_date, "…T07:00:00"): the
// campaign clock's days and hours are then the calendar's. 0 when the date has no time.
double ClockZeroTimeOfDayS(const std::string& start_date) {
  const auto t = start_date.find('T');
  if (t == std::string::npos) return 0;
  int h = 0, m = 0;
  double s = 0;
  if (std::sscanf(start_date.c_str() + t + 1, "%d:%d:%lf", &h, &m, &s) < 2) return 0;
  return h * 3600.0 + m * 60.0 + s;
}

std::string Range(double lo, double hi) { return fmt::format("{:.1f}–{:.1f} °C", lo, hi); }

}  // namespace

bool CampaignCheckResult::Complete() const {
  if (!file_problems.empty()) return false;
  for (const auto& a : axes)
    if (!a.missing.empty()) return false;
  return true;
}

CampaignCheckResult CheckCampaign(const std::string& dir, const CheckOptions& o) {
  CampaignCheckResult res;
  const fs::path base(dir);
  res.manifest_path = (base / measure::kCampaignManifestFile).string();
  if (!fs::exists(res.manifest_path))
    throw InputError(res.manifest_path, 0, "", "no campaign here: `trueaxis campaign plan` writes manifest.json");
  res.manifest = measure::ReadCampaignManifest(res.manifest_path);
  const auto& man = res.manifest;

  // The temperature log.
  std::optional<measure::TemperatureLog> log;
  const std::string log_path = (base / man.temperature_log).string();
  if (!fs::exists(log_path)) {
    res.file_problems.push_back(fmt::format("{}: missing — no test has its temperatures", man.temperature_log));
  } else {
    try {
      log = measure::ReadTemperatureLog(log_path, true);
      res.log_rows = log->time_s.size();
      if (res.log_rows) res.log_first_s = log->time_s.front(), res.log_last_s = log->time_s.back();
      else if (!man.measurements.empty())
        res.file_problems.push_back(fmt::format("{}: no rows yet — start `trueaxis campaign log` before the tests",
                                                man.temperature_log));
    } catch (const InputError& e) {
      res.file_problems.push_back(e.what());
    }
  }
  const double step_s = log ? LogStepS(*log) : 60;

  // Each entry: the file, its time, its temperatures.
  std::vector<EntryFacts> facts;
  std::set<std::string> seen_files;
  std::map<std::string, double> cte_of_axis;  // from the files' `# cte_um_per_m_c:`
  for (std::size_t i = 0; i < man.measurements.size(); ++i) {
    const auto& e = man.measurements[i];
    EntryFacts f;
    f.entry = &e;
    f.start_s = e.start_time_s;
    f.end_s = e.end_time_s;
    const std::string where = fmt::format("measurements[{}] {}", i, e.file);
    if (!seen_files.insert(e.file).second) res.file_problems.push_back(where + ": listed twice (it would count twice in the fit)");
    std::optional<measure::Measurement> m;
    const fs::path p = fs::path(e.file).is_relative() ? base / e.file : fs::path(e.file);
    if (!fs::exists(p)) {
      res.file_problems.push_back(where + ": the file is missing");
    } else {
      try {
        m = measure::ReadMeasurementFile(p.string());
        if (const auto cte = m->Meta("cte_um_per_m_c"))
          if (const auto v = ParseDouble(std::string(Trim(*cte)))) cte_of_axis[e.axis] = *v;
        const auto file_axis = m->Meta("axis");
        if (file_axis && !std::string(Trim(*file_axis)).empty() && LowerAscii(std::string(Trim(*file_axis))) != LowerAscii(e.axis))
          res.file_problems.push_back(fmt::format("{}: the manifest says axis {}, the file says '{}'", where, e.axis, *file_axis));
      } catch (const InputError& err) {
        res.file_problems.push_back(fmt::format("{}: unreadable: {}", where, err.what()));
      }
    }
    if (std::isnan(f.end_s) && std::isfinite(f.start_s) && m) {
      double last = 0;
      for (const auto& pt : m->points)
        if (pt.time_s) last = std::max(last, *pt.time_s);
      f.end_s = f.start_s + last;
    }
    if (std::isnan(f.end_s)) f.end_s = f.start_s;
    if (std::isnan(f.start_s)) {
      res.file_problems.push_back(where + ": no start_time_s — its time on the campaign clock is not known, so the "
                                          "fit cannot give it the hours before it (add it with `trueaxis campaign add`)");
    } else if (log && !log->time_s.empty()) {
      // A row near the start and one within the test: else the log has nothing at its time.
      double nearest = std::numeric_limits<double>::infinity();
      for (double t : log->time_s) nearest = std::min(nearest, std::abs(t - f.start_s));
      if (nearest > 2 * step_s)
        res.file_problems.push_back(fmt::format(
            "{}: no temperatures in the log at its time ({} s on the campaign clock; the log's nearest row is {:.0f} s "
            "away, the log covers {}–{} s): was `campaign log` running?",
            where, FormatShortest(f.start_s), nearest, FormatShortest(log->time_s.front()),
            FormatShortest(log->time_s.back())));
      else
        for (const std::string& key : {man.NutSensor(e.axis), man.SensorsAt("ambient").empty() ? std::string()
                                                                                                  : man.SensorsAt("ambient").front()}) {
          if (key.empty()) continue;
          const int col = log->SensorIndex(key);
          if (col < 0)
            res.file_problems.push_back(fmt::format("{}: the log has no column t_{}_c", where, key));
          else if (std::isnan(LogMean(*log, col, f.start_s - 2 * step_s, f.end_s + 2 * step_s)))
            res.file_problems.push_back(fmt::format("{}: the log has no {} reading at its time (the sensor was "
                                                    "flagged or unplugged)", where, key));
        }
    }
    for (const auto& s : man.sensors) {
      double v = e.MeanTemperatureC(s);
      if (std::isnan(v) && log && std::isfinite(f.start_s)) v = LogMean(*log, log->SensorIndex(s), f.start_s, f.end_s);
      if (std::isnan(v) && m) v = FileMean(*m, s);
      f.mean_c[s] = v;
    }
    facts.push_back(f);
  }

  // Axes: the campaign's, then any other an entry names.
  std::vector<std::string> axes = man.axes;
  for (const auto& e : man.measurements)
    if (std::find(axes.begin(), axes.end(), e.axis) == axes.end()) axes.push_back(e.axis);

  std::vector<sim::CampaignFile> gap_files;
  const auto& rules = o.rules;
  const double tod_s = ClockZeroTimeOfDayS(man.start_date);
  const auto day_of = [tod_s](double t) { return static_cast<int>(std::floor((t + tod_s) / 86400)); };
  for (const auto& axis : axes) {
    AxisCoverage c;
    c.axis = axis;
    const std::string nut = man.NutSensor(axis);
    const auto rooms = man.SensorsAt("ambient");
    double cold_nut = kNaN;
    std::vector<const EntryFacts*> mine;
    for (const auto& f : facts)
      if (f.entry->axis == axis) mine.push_back(&f);
    for (const auto* f : mine) {
      const auto& e = *f->entry;
      ++c.tests[e.state];
      if (e.state == "cold" && std::isnan(cold_nut) && !nut.empty()) cold_nut = f->mean_c.at(nut);
      if (e.state == "coolant" || e.state == "coolant_rest") c.coolants.insert(e.coolant);
    }
    const EntryFacts* last_warm = nullptr;
    for (const auto* f : mine) {
      const auto& e = *f->entry;
      double rise = e.nut_rise_c;
      if (std::isnan(rise) && !nut.empty()) rise = f->mean_c.at(nut) - cold_nut;
      if (e.state == "warm") {
        if (std::isfinite(rise)) c.max_nut_rise_c = std::max(c.max_nut_rise_c, rise);
        last_warm = f;
      }
      if (e.state == "ambient" && std::isfinite(f->start_s)) {
        c.ambient_days.insert(day_of(f->start_s));
        c.ambient_hours.insert(static_cast<int>(std::floor(std::fmod(f->start_s + tod_s, 86400) / 3600)));
      }
      if ((e.state == "warm" || e.state == "coolant") && std::isfinite(rise)) {
        sim::CampaignFile g;
        g.axis = axis;
        g.state = e.state;
        g.nut_rise_c = rise;
        g.coolant_session = e.coolant_session;
        gap_files.push_back(g);
      }
    }
    // Saturation: the nut's rise over the window before the last warm-up test.
    if (last_warm && log && !nut.empty() && std::isfinite(last_warm->start_s)) {
      const int col = log->SensorIndex(nut);
      const double window_s = rules.saturation_window_min * 60;
      // One-minute means of the nut, the window apart (as the warm-up rule watches it).
      const double before = LogMean(*log, col, last_warm->start_s - window_s - 60, last_warm->start_s - window_s);
      const double at = LogMean(*log, col, last_warm->start_s - 60, last_warm->start_s);
      if (std::isfinite(before) && std::isfinite(at)) {
        c.rise_before_last_warm_c = at - before;
        // Judged afterwards from the log's rows, the rule's threshold with half of it again as room:
        // two one-minute means of 30-s rows scatter more than what the warm-up rule watched live.
        constexpr double kAfterwardsTolerance = 1.5;
        c.saturation = std::abs(at - before) < kAfterwardsTolerance * rules.saturation_rise_c ? 1 : 0;
      }
    }
    // Temperature ranges of the key sensors over this axis's tests.
    c.room_min_c = c.room_max_c = kNaN;
    for (const auto& s : man.sensors) {
      const std::string loc = man.LocationOf(s);
      if (!KeyLocation(loc, axis)) continue;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto* f : mine) {
        const double v = f->mean_c.at(s);
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
      if (!(lo <= hi)) continue;
      c.ranges.push_back({s, loc, lo, hi});
      if (loc == "ambient") {
        c.room_min_c = std::isnan(c.room_min_c) ? lo : std::min(c.room_min_c, lo);
        c.room_max_c = std::isnan(c.room_max_c) ? hi : std::max(c.room_max_c, hi);
      }
    }

    // What is missing, and what to measure for it.
    auto n = [&](const char* state) { return c.tests.count(state) ? c.tests.at(state) : 0; };
    if (mine.empty()) c.missing.push_back("no test at all: start with the cold test after an overnight soak");
    else if (n("cold") == 0)
      c.missing.push_back("no cold test: every state is measured against the cold machine; measure one in the morning "
                          "after an overnight soak, before the axes move");
    if (!mine.empty() && n("warm") == 0)
      c.missing.push_back("no warm-up tests: run the warm-up program and measure as the nut rises (plan.md)");
    else if (n("warm") > 0 && n("warm") < 3)
      c.missing.push_back(fmt::format("only {} warm-up test(s): the nut's rise is sampled at too few points; take the "
                                      "next test each time the nut has risen the next step", n("warm")));
    if (n("warm") > 0 && c.saturation == 0)
      c.missing.push_back(fmt::format("the warm-up stopped before saturation (the nut still rose {:.2f} °C in the {} min "
                                      "before the last test): the hot end of a working day is extrapolated; warm up "
                                      "until the nut rises less than {} °C in {} min",
                                      c.rise_before_last_warm_c, rules.saturation_window_min, rules.saturation_rise_c,
                                      rules.saturation_window_min));
    if (!mine.empty() && n("cooldown") == 0)
      c.missing.push_back("no cool-down test: the nut and the screw cooling at different rates are never seen; after "
                          "saturation stop the axes and measure as the nut falls");
    const int cold_day = [&] {
      for (const auto* f : mine)
        if (f->entry->state == "cold" && std::isfinite(f->start_s)) return day_of(f->start_s);
      return -1;
    }();
    std::set<int> other_days = c.ambient_days;
    other_days.erase(cold_day);
    if (!mine.empty() && other_days.empty())
      c.missing.push_back("no test on another day: the machine idle on another day (and another season) shows the model "
                          "the machine following the room; measure the idle machine at night, in the morning and in "
                          "the evening");
    else if (!other_days.empty() && *other_days.rbegin() - std::min(cold_day, *other_days.begin()) < 30)
      c.missing.push_back(fmt::format("the other days lie within {} days of each other: no other season; measure the "
                                      "idle machine again in two or three months",
                                      *other_days.rbegin() - std::min(cold_day, *other_days.begin())));
    if (!mine.empty() && c.coolants.empty())
      c.missing.push_back("no coolant test: if the machine works with coolant, the model does not know its effect; "
                          "measure a warm-up with the coolant on (or ignore this for a dry machine)");
    if (const auto it = cte_of_axis.find(axis); it != cte_of_axis.end()) c.cte_um_per_m_c = it->second;
    if (!rooms.empty() && std::isnan(c.cte_um_per_m_c) && !mine.empty())
      c.missing.push_back(fmt::format(
          "no CTE of the axis's feedback (cte_um_per_m_c on the axis in the machine file, then `campaign plan` again; "
          "or fit --cte): the fit then takes the room's soak from these tests' room changes, and a room outside them "
          "(another season) extrapolates that fit instead of the screw's physical growth"));
    if (rooms.empty()) {
      c.missing.push_back("no room (ambient) sensor in the campaign: the model's reach in room temperature is unknown");
    } else if (std::isnan(c.room_min_c)) {
      if (!mine.empty()) c.missing.push_back("no room temperature read during any test");
    } else {
      if (c.room_max_c < o.room_high_c)
        c.missing.push_back(fmt::format("no measurement with the room above {:.1f} °C: a day warmer than that (the "
                                        "workshop reaches {} °C) is extrapolated; measure one warm afternoon",
                                        c.room_max_c, o.room_high_c));
      if (c.room_min_c > o.room_low_c)
        c.missing.push_back(fmt::format("no measurement with the room below {:.1f} °C: a day colder than that (the "
                                        "workshop falls to {} °C) is extrapolated; measure one cold early morning",
                                        c.room_min_c, o.room_low_c));
    }
    res.axes.push_back(std::move(c));
  }
  res.warm_up_gaps = sim::WarmUpCoverageGaps(gap_files);
  return res;
}

std::string CheckReport(const CampaignCheckResult& r) {
  const auto& man = r.manifest;
  std::string out = fmt::format("Campaign {}: {} test(s) in {}", man.machine.empty() ? "(unnamed)" : man.machine,
                                man.measurements.size(), r.manifest_path);
  out += r.log_rows ? fmt::format("; temperature log {} rows, {:.1f}–{:.1f} h on the campaign clock\n", r.log_rows,
                                  r.log_first_s / 3600, r.log_last_s / 3600)
                    : std::string("; temperature log empty\n");
  for (const auto& c : r.axes) {
    int total = 0;
    for (const auto& [s, k] : c.tests) total += k;
    out += fmt::format("\nAxis {}: {} test(s)\n", c.axis, total);
    for (const auto& state : measure::CampaignStates()) {
      const int k = c.tests.count(state) ? c.tests.at(state) : 0;
      std::string detail;
      if (state == "warm" && k > 0) {
        detail = fmt::format("nut rise up to {:+.1f} °C", c.max_nut_rise_c);
        if (c.saturation == 1) detail += fmt::format(", saturation reached ({:+.2f} °C over the window before the last)", c.rise_before_last_warm_c);
        else if (c.saturation == 0) detail += ", saturation NOT reached";
        else detail += ", saturation unknown (no log before the last test)";
      }
      if (state == "ambient" && k > 0) {
        std::vector<std::string> days, hours;
        for (int d : c.ambient_days) days.push_back(std::to_string(d));
        for (int h : c.ambient_hours) hours.push_back(fmt::format("{:02}:00", h));
        detail = fmt::format("campaign day(s) {} at {}", fmt::join(days, ", "), fmt::join(hours, ", "));
      }
      if ((state == "coolant" || state == "coolant_rest") && k > 0) detail = fmt::format("{}", fmt::join(c.coolants, ", "));
      out += fmt::format("  {:<13}{:>3}{}\n", state, k, detail.empty() ? "" : "   " + detail);
    }
    if (!c.ranges.empty()) {
      out += "  temperatures over the tests:";
      for (const auto& s : c.ranges)
        out += fmt::format(" {}{} {};", s.sensor, s.location == s.sensor ? "" : " (" + s.location + ")", Range(s.min_c, s.max_c));
      out.back() = '\n';
    }
    if (std::isfinite(c.room_min_c))
      out += std::isnan(c.cte_um_per_m_c)
                 ? fmt::format("  the model can vouch for room temperatures {} (measured); outside, it extrapolates\n",
                               Range(c.room_min_c, c.room_max_c))
                 : fmt::format("  the model can vouch for room temperatures {} (measured); outside, the room's soak "
                               "still holds (ρ from the CTE {} µm/m/°C), its fitted thermal terms extrapolate\n",
                               Range(c.room_min_c, c.room_max_c), FormatShortest(c.cte_um_per_m_c));
    if (c.missing.empty()) out += "  missing: nothing\n";
    else {
      out += "  missing:\n";
      for (const auto& m : c.missing) out += "    - " + m + "\n";
    }
  }
  if (!r.warm_up_gaps.empty()) {
    out += "\nWarm-ups with most of their rise between two tests:\n";
    for (const auto& g : r.warm_up_gaps) out += "  - " + g + "\n";
  }
  if (!r.file_problems.empty()) {
    out += "\nFile problems:\n";
    for (const auto& p : r.file_problems) out += "  - " + p + "\n";
  }
  out += r.Complete() ? "\nCoverage: complete — fit with `trueaxis fit --manifest manifest.json`\n"
                      : "\nCoverage: incomplete (above: what is missing and what to measure)\n";
  return out;
}

}  // namespace trueaxis::campaign
