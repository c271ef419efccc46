#include "trueaxis/campaign/campaign_plan.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/campaign/laser_program.hpp"
#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::campaign {
namespace {

namespace fs = std::filesystem;
using Visit = sim::CampaignOptions::CoolantVisit;

std::string HourText(double hour) {
  const int minutes = static_cast<int>(std::lround(hour * 60));
  return fmt::format("{:02}:{:02}", minutes / 60, minutes % 60);
}

// "2026-03-02" + days, or "day N" when no start date was given.
std::string DayText(const std::string& start, int offset) {
  if (start.empty()) return fmt::format("day {}", offset);
  int y = 0;
  unsigned m = 0, d = 0;
  std::sscanf(start.c_str(), "%d-%u-%u", &y, &m, &d);
  using namespace std::chrono;
  const year_month_day ymd{sys_days{year{y} / month{m} / day{d}} + days{offset}};
  return fmt::format("{:04}-{:02}-{:02}", static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                     static_cast<unsigned>(ymd.day()));
}

void CheckStartDate(const std::string& s) {
  if (s.empty()) return;
  int y = 0;
  unsigned m = 0, d = 0;
  char tail = 0;
  const bool parsed = std::sscanf(s.c_str(), "%d-%u-%u%c", &y, &m, &d, &tail) == 3;
  using namespace std::chrono;
  if (!parsed || !year_month_day{year{y} / month{m} / day{d}}.ok() || y < 2000 || y > 2200)
    throw InputError("command line", 0, "--start-date", fmt::format("'{}' is not a date YYYY-MM-DD", s));
}

std::string Minutes(double s) { return s < 5400 ? fmt::format("{:.0f} min", s / 60) : fmt::format("{:.1f} h", s / 3600); }

}  // namespace

CampaignPlan MakeCampaignPlan(const CampaignMachine& machine, const PlanOptions& o) {
  CampaignPlan plan;
  plan.machine = machine;
  plan.options = o;
  CheckStartDate(o.start_date);
  {
    sim::CampaignOptions check = o.schedule;
    check.out_dir = o.out_dir.empty() ? "." : o.out_dir;
    std::string why;
    if (!check.IsValid(&why)) throw InputError("command line", 0, "", why);
  }
  if (o.axes.empty()) {
    for (const auto& a : machine.axes) plan.axes.push_back(a.name);
  } else {
    for (const auto& name : o.axes) {
      const int i = machine.AxisIndex(name);
      if (i < 0) throw InputError("command line", 0, "--axes", fmt::format("{} has no axis '{}'", machine.source, name));
      const std::string& n = machine.axes[static_cast<std::size_t>(i)].name;
      if (std::find(plan.axes.begin(), plan.axes.end(), n) == plan.axes.end()) plan.axes.push_back(n);
    }
  }
  for (const auto& name : plan.axes) {
    const auto& axis = machine.axes[static_cast<std::size_t>(machine.AxisIndex(name))];
    plan.targets.push_back(PlanAxisTargets(axis, o.targets));
  }
  plan.controllers = !o.controllers.empty() ? o.controllers
                     : machine.controller   ? std::vector<Controller>{*machine.controller}
                                            : AllControllers();

  // The schedule: the virtual campaign's order (src/sim/campaign.cpp Campaign::Run).
  const auto& s = o.schedule;
  const std::string coolant_name(CoolantStateName(s.coolant_state));
  int day = 0;
  for (const auto& a : plan.axes) {
    plan.steps.push_back({day, 7, a, "cold", "off", o.targets.runs, 1,
                          "machine off overnight (≥ 12 h, doors shut, no heating change): set up the laser, zero it "
                          "at the reference, run the laser test"});
    plan.steps.push_back({day, 7.5, a, "warm", "off", s.warm_runs, s.max_warm_measurements,
                          "run the warm-up program; a laser test each time the nut has risen the next step (below), "
                          "the last at saturation"});
    if (s.cooldown_measurements > 0)
      plan.steps.push_back({day, 13, a, "cooldown", "off", s.warm_runs, s.cooldown_measurements,
                            fmt::format("stop all axes; a laser test each time the nut has fallen another {} °C "
                                        "(within {} h)", s.cooldown_step_c, s.max_cooldown_hours)});
    ++day;
  }
  const auto coolant_sessions = [&]() {
    if (!s.coolant_session || s.max_coolant_measurements <= 0) return;
    for (double prewarm : s.coolant_prewarm_h)
      for (const auto& a : plan.axes) {
        plan.steps.push_back(
            {day, 7, a, "coolant", coolant_name, s.warm_runs, s.max_coolant_measurements,
             (prewarm > 0 ? fmt::format("{} h of dry warm-up first; then ", prewarm) : std::string("cold machine; ")) +
                 fmt::format("coolant ({}) on, a laser test at once ({} runs), then the warm-up program with the "
                             "coolant running, tests by the nut rule (up to {} in all)",
                             coolant_name, o.targets.runs, s.max_coolant_measurements)});
        if (s.coolant_rest && s.cooldown_measurements > 0)
          plan.steps.push_back({day, 12, a, "coolant_rest", coolant_name, s.warm_runs, s.cooldown_measurements,
                                fmt::format("stop the axes, coolant still running; a laser test each time the nut has "
                                            "fallen another {} °C", s.cooldown_step_c)});
        ++day;
      }
  };
  if (s.coolant_visit != Visit::kAfterSeasons) coolant_sessions();
  for (int offset : s.ambient_day_offsets) {
    for (double hour : s.ambient_hours)
      for (const auto& a : plan.axes)
        plan.steps.push_back({offset, hour, a, "ambient", "off", o.targets.runs, 1,
                              "machine idle since the evening before (no warm-up): the laser test only"});
    day = std::max(day, offset + 1);
  }
  if (s.coolant_visit != Visit::kFirstVisit) coolant_sessions();
  return plan;
}

std::string PlanMarkdown(const CampaignPlan& plan) {
  const auto& o = plan.options;
  const auto& s = o.schedule;
  const auto& m = plan.machine;
  std::string md = fmt::format("# Calibration campaign: {}\n\n", m.name);
  md += fmt::format(
      "Planned from `{}` by `trueaxis campaign plan`. Axes {}. Follow the schedule below; after each laser test add "
      "its file with `trueaxis campaign add`, keep `trueaxis campaign log` recording the temperatures the whole time, "
      "and run `trueaxis campaign check .` to see what is covered and what is missing "
      "(docs/real-machine.md).\n\n",
      m.source, fmt::join(plan.axes, ", "));

  md += "## Before the first day\n\n";
  md += "- Sensors (the log's columns; mount them as docs/real-machine.md shows):\n\n| sensor | location |\n|---|---|\n";
  for (const auto& sensor : m.sensors) md += fmt::format("| `{}` | {} |\n", sensor.name, sensor.location);
  md += "\n- Start `trueaxis campaign log` in this folder before the first cold test and keep it running through "
        "every test day (it writes `temperature_log.csv`; the fit reads the hours before each test from it).\n"
        "- Switch the axis's pitch and thermal compensation **off** for the tests (the fit needs the machine's own "
        "error); keep backlash compensation as it will be in production.\n"
        "- Laser: linear optics on the axis, air and material sensors on, material sensor on the table. Zero the "
        "laser at the axis's reference position (table below) and leave the tripod in place for the whole day.\n\n";

  md += "## Targets (ISO 230-2)\n\n";
  md += "Every state is measured at the same targets. Target i sits at P₁ + (i − 1)·p + rᵢ: p the even spacing, "
        "rᵢ a different random value at each inner target (|rᵢ| ≤ the bound below: the lead's periodic error is "
        "sampled at many phases), the first and last at the ends of the measurement travel, with the overrun beyond "
        "each end for the reversal inside the soft limits.\n\n";
  md += "| axis | limits mm | reference mm | targets | p mm | r within ± mm | overrun mm | dwell s | feed mm/min | "
        "test (runs) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < plan.axes.size(); ++i) {
    const auto& t = plan.targets[i];
    const auto& a = m.axes[static_cast<std::size_t>(m.AxisIndex(t.axis))];
    md += fmt::format("| {} | {} … {} | {} | {} from {} to {} | {:.3f} | {:.3f} | {} | {} | {} | {} ({}), {} ({}) |\n",
                      t.axis, a.min_mm, a.max_mm, a.reference_mm, t.targets_mm.size(), t.targets_mm.front(),
                      t.targets_mm.back(), t.spacing_mm, t.random_max_mm, t.overrun_mm, t.dwell_s, t.feed_mm_min,
                      Minutes(TestDurationS(t, o.targets.runs)), o.targets.runs,
                      Minutes(TestDurationS(t, s.warm_runs)), s.warm_runs);
  }
  md += "\nTarget lists (mm, machine coordinates):\n\n";
  for (const auto& t : plan.targets) {
    std::vector<std::string> v;
    for (double x : t.targets_mm) v.push_back(fmt::format("{:.3f}", x));
    md += fmt::format("- {}: {}\n", t.axis, fmt::join(v, ", "));
  }
  md += "\nEnter the same list in the laser software (target list, bidirectional, stop/dwell trigger), or let it "
        "trigger on the dwell of the programs below.\n\n";

  md += "## Programs\n\n";
  md += fmt::format("In `programs/`: per axis the laser test ({} runs, for cold, ambient and the first coolant test) "
                    "and the short test ({} runs, for warm-up, cool-down and coolant tests), and the warm-up "
                    "(all axes reciprocating, strokes at {} and {} mm/min, until you stop it). Prove them in single "
                    "block with the feed override low before the first test.\n\n",
                    o.targets.runs, s.warm_runs, s.warmup_feed_low_mm_min, s.warmup_feed_high_mm_min);
  for (Controller c : plan.controllers) md += fmt::format("- {}: `programs/{}/`\n", ControllerTitle(c), ControllerName(c));

  md += "\n## When to take the next test\n\n";
  md += fmt::format(
      "- **Warm-up** (states `warm`, `coolant`): watch the nut sensor's one-minute mean against the axis's cold "
      "test (`campaign log` shows it and says when the next test is due). Take the next test when the nut has risen "
      "another step above the previous test's rise. The step is the largest of {} °C, {:.0f} % of the rise so far, "
      "and the even share, over the tests still allowed, of the rise still to come (extrapolated from the warm-up "
      "curve once it bends). Between two dry warm-up tests machine at least {} × the last test's duration. At most "
      "{} tests per warm-up ({} with coolant); the last one at **saturation**: the nut rose less than {} °C in {} min "
      "of warm-up — or after {} h of warm-up.\n",
      s.nut_step_c, 100 * s.nut_step_growth, s.min_warmup_per_test, s.max_warm_measurements,
      s.max_coolant_measurements, s.saturation_rise_c, s.saturation_window_min, s.max_warmup_hours);
  md += fmt::format("- **Cool-down** (`cooldown`, `coolant_rest`): all axes stopped; a test each time the nut has "
                    "fallen another {} °C, {} tests, within {} h.\n",
                    s.cooldown_step_c, s.cooldown_measurements, s.max_cooldown_hours);
  md += "- **Ambient**: the idle machine, no warm-up since the evening before: another season and other hours, so the "
        "model sees the machine follow the room (03:00 the room at its coldest, 10:00 rising, 19:00 falling). An "
        "hour the day's earlier tests ran past: take it the next day.\n\n";

  md += "## Schedule\n\n| day | time | axis | state | coolant | runs | tests | what to do |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& st : plan.steps)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {}{} | {} |\n", DayText(o.start_date, st.day), HourText(st.hour),
                      st.axis, st.state, st.coolant, st.runs, st.state == "warm" || st.state == "coolant" ? "≤ " : "",
                      st.max_tests, st.what);
  md += "\nTimes after the cold test are when a state typically starts; the rules above decide.\n\n";

  md += "## After each test\n\n```\ntrueaxis campaign add . LASERFILE --axis X --state warm\ntrueaxis campaign check .\n"
        "```\n\nWhen `campaign check` reports the states covered: `trueaxis fit --manifest manifest.json --out "
        "model.json`, then export the tables or run the compensation (docs/real-machine.md).\n";
  return md;
}

std::string PlanJson(const CampaignPlan& plan) {
  const auto& s = plan.options.schedule;
  nlohmann::ordered_json j;
  j["format"] = "trueaxis-campaign-plan";
  j["version"] = 1;
  j["machine"] = plan.machine.name;
  j["machine_file"] = plan.machine.source;
  j["start_date"] = plan.options.start_date;
  j["seed"] = plan.options.targets.seed;
  auto& axes = j["axes"] = nlohmann::ordered_json::array();
  for (const auto& t : plan.targets) {
    const auto& a = plan.machine.axes[static_cast<std::size_t>(plan.machine.AxisIndex(t.axis))];
    nlohmann::ordered_json e;
    e["axis"] = t.axis;
    e["min_mm"] = a.min_mm;
    e["max_mm"] = a.max_mm;
    e["lead_mm"] = a.lead_mm;
    e["fixed_end"] = a.fixed_at_min ? "min" : "max";
    e["reference_mm"] = a.reference_mm;
    if (std::isfinite(a.cte_um_per_m_c)) e["cte_um_per_m_c"] = a.cte_um_per_m_c;
    e["runs"] = plan.options.targets.runs;
    e["short_runs"] = s.warm_runs;
    e["overrun_mm"] = t.overrun_mm;
    e["dwell_s"] = t.dwell_s;
    e["feed_mm_min"] = t.feed_mm_min;
    e["spacing_mm"] = std::round(t.spacing_mm * 1e6) / 1e6;
    e["random_max_mm"] = std::round(t.random_max_mm * 1e6) / 1e6;
    e["targets_mm"] = t.targets_mm;
    axes.push_back(e);
  }
  auto& r = j["rules"];
  r["nut_step_c"] = s.nut_step_c;
  r["nut_step_growth"] = s.nut_step_growth;
  r["min_warmup_per_test"] = s.min_warmup_per_test;
  r["max_warm_tests"] = s.max_warm_measurements;
  r["max_coolant_tests"] = s.max_coolant_measurements;
  r["saturation_window_min"] = s.saturation_window_min;
  r["saturation_rise_c"] = s.saturation_rise_c;
  r["max_warmup_hours"] = s.max_warmup_hours;
  r["cooldown_tests"] = s.cooldown_measurements;
  r["cooldown_step_c"] = s.cooldown_step_c;
  r["max_cooldown_hours"] = s.max_cooldown_hours;
  r["warmup_feeds_mm_min"] = {s.warmup_feed_low_mm_min, s.warmup_feed_high_mm_min};
  auto& steps = j["steps"] = nlohmann::ordered_json::array();
  for (const auto& st : plan.steps)
    steps.push_back({{"day", st.day}, {"hour", st.hour}, {"axis", st.axis}, {"state", st.state},
                     {"coolant", st.coolant}, {"runs", st.runs}, {"max_tests", st.max_tests}});
  return j.dump(2) + "\n";
}

std::vector<std::string> WriteCampaignFolder(const CampaignPlan& plan) {
  const fs::path dir(plan.options.out_dir);
  const fs::path manifest_path = dir / measure::kCampaignManifestFile;
  if (fs::exists(manifest_path))
    throw InputError(manifest_path.string(), 0, "",
                     "a campaign already lives in this folder; plan into a new folder (a campaign is never "
                     "overwritten)");
  fs::create_directories(dir);
  std::vector<std::string> written;
  const auto write = [&](const std::string& rel, const std::string& text) {
    const fs::path p = dir / rel;
    fs::create_directories(p.parent_path());
    WriteTextFile(p.string(), text);
    written.push_back(rel);
  };
  write("plan.md", PlanMarkdown(plan));
  write("plan.json", PlanJson(plan));
  const auto& s = plan.options.schedule;
  for (Controller c : plan.controllers) {
    const std::string sub = fmt::format("programs/{}/", ControllerName(c));
    for (std::size_t i = 0; i < plan.axes.size(); ++i) {
      const auto& axis = plan.machine.axes[static_cast<std::size_t>(plan.machine.AxisIndex(plan.axes[i]))];
      const int number = 7000 + 10 * static_cast<int>(i);
      const ProgramFile full = LaserTestProgram(c, plan.machine, axis, plan.targets[i], plan.options.targets.runs, number + 1);
      write(sub + full.file_name, full.text);
      const ProgramFile brief = LaserTestProgram(c, plan.machine, axis, plan.targets[i], s.warm_runs, number + 2);
      write(sub + brief.file_name, brief.text);
    }
    const ProgramFile warm = WarmUpProgram(c, plan.machine, plan.axes, s.warmup_feed_low_mm_min,
                                           s.warmup_feed_high_mm_min, 7900);
    write(sub + warm.file_name, warm.text);
  }
  measure::CampaignManifest manifest;
  manifest.machine = plan.machine.name;
  manifest.machine_file = plan.machine.source;
  manifest.axes = plan.axes;
  std::vector<std::string> log_axes;
  for (const auto& a : plan.machine.axes) log_axes.push_back(a.name);
  for (const auto& sensor : plan.machine.sensors) {
    manifest.sensors.push_back(sensor.name);
    if (sensor.location != sensor.name) manifest.sensor_locations[sensor.name] = sensor.location;
  }
  write(std::string(measure::kCampaignLogFile), measure::CampaignLogHeader(log_axes, manifest.sensors));
  write(std::string(measure::kCampaignManifestFile), measure::CampaignManifestJson(manifest));
  return written;
}

}  // namespace trueaxis::campaign
