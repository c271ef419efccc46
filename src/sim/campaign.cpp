#include "trueaxis/sim/campaign.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <vector>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <tuple>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/sim/warmup_rule.hpp"
#include "trueaxis/sim/machine_log.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

bool CampaignOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (out_dir.empty()) return fail("out_dir is empty");
  if (!laser.IsValid(why)) return false;
  if (!(warmup_feed_low_mm_min > 0 && warmup_feed_high_mm_min > 0)) return fail("warm-up feeds must be positive");
  if (!(nut_step_c > 0)) return fail("nut_step_c must be positive");
  if (!(min_warmup_per_test >= 0 && min_warmup_per_test <= 10)) return fail("min_warmup_per_test must be 0–10");
  if (!(nut_step_growth >= 0 && nut_step_growth <= 1)) return fail("nut_step_growth must be in 0–1");
  if (cooldown_measurements < 0 || cooldown_measurements > 20) return fail("cooldown_measurements must be 0–20");
  if (!(cooldown_step_c > 0) || !(max_cooldown_hours > 0)) return fail("cooldown step and time cap must be positive");
  if (warm_runs < 2 || warm_runs > 20) return fail("warm_runs must be 2–20");
  if (max_warm_measurements < 1 || max_warm_measurements > 100) return fail("max_warm_measurements must be 1–100");
  if (max_coolant_measurements < 0 || max_coolant_measurements > 100) return fail("max_coolant_measurements must be 0–100");
  if (!(max_warmup_hours > 0 && max_warmup_hours <= 48)) return fail("max_warmup_hours must be in (0, 48]");
  if (!(saturation_window_min > 0) || !(saturation_rise_c > 0)) return fail("saturation window and rise must be positive");
  for (int d : ambient_day_offsets)
    if (d < 1 || d > 3650) return fail("ambient_day_offsets must be 1–3650 days");
  if (!ambient_day_offsets.empty() && ambient_hours.empty()) return fail("ambient_hours must name at least one hour");
  for (std::size_t i = 0; i < ambient_hours.size(); ++i) {
    if (!(ambient_hours[i] >= 0 && ambient_hours[i] < 24))
      return fail(fmt::format("ambient_hours: {} is not an hour of the day in [0, 24)", ambient_hours[i]));
    if (i > 0 && !(ambient_hours[i] > ambient_hours[i - 1]))
      return fail("ambient_hours must be in increasing order (the measurements of one day follow each other)");
  }
  if (!(log_interval_s > 0)) return fail("log_interval_s must be positive");
  if (coolant_session && coolant_prewarm_h.empty())
    return fail("coolant_prewarm_h must name at least one coolant session (0: over the cold machine)");
  for (double h : coolant_prewarm_h)
    if (!(h >= 0 && h <= 12)) return fail(fmt::format("coolant_prewarm_h: {} h is not in [0, 12]", h));
  return true;
}

std::optional<CampaignOptions::CoolantVisit> ParseCoolantVisit(std::string_view name) {
  using V = CampaignOptions::CoolantVisit;
  for (V v : {V::kAfterSeasons, V::kFirstVisit, V::kBoth})
    if (name == CoolantVisitName(v)) return v;
  return std::nullopt;
}

const char* CoolantVisitName(CampaignOptions::CoolantVisit visit) {
  switch (visit) {
    case CampaignOptions::CoolantVisit::kAfterSeasons: return "after-seasons";
    case CampaignOptions::CoolantVisit::kFirstVisit: return "first";
    case CampaignOptions::CoolantVisit::kBoth: return "both";
  }
  return "both";
}

std::string CampaignSummary::BriefReport() const {
  std::map<std::string, int> by_state;
  for (const auto& f : files) ++by_state[f.state];
  std::string s = fmt::format("{} measurement files (", files.size());
  bool first = true;
  for (const auto& [k, v] : by_state) {
    s += fmt::format("{}{} {}", first ? "" : ", ", v, k);
    first = false;
  }
  s += fmt::format("), {:.1f} h of machine time in {:.2f} s", machine_time_s / 3600.0, wall_time_s);
  for (const auto& gap : WarmUpCoverageGaps(files)) s += "\n  " + gap;
  return s;
}

std::vector<std::string> WarmUpCoverageGaps(const std::vector<CampaignFile>& files, double max_gap_fraction) {
  // (axis, state, coolant session) → rises in test order
  std::map<std::tuple<std::string, std::string, int>, std::vector<double>> rises;
  int sessions = 0;
  for (const auto& f : files) {
    if (f.state == "warm" || f.state == "coolant") rises[{f.axis, f.state, f.coolant_session}].push_back(f.nut_rise_c);
    sessions = std::max(sessions, f.coolant_session);
  }
  std::vector<std::string> out;
  for (const auto& [key, r] : rises) {
    const auto& [axis, state, session] = key;
    std::vector<double> steps = r;
    if (state == "warm") steps.insert(steps.begin(), 0.0);  // the cold state is the warm-up's start
    if (steps.size() < 2) continue;
    // A session over a warm machine first falls to the coolant: its span is the tests' whole range.
    const double lo = *std::min_element(steps.begin(), steps.end()), hi = *std::max_element(steps.begin(), steps.end());
    double gap = 0;
    for (std::size_t i = 1; i < steps.size(); ++i) gap = std::max(gap, std::fabs(steps[i] - steps[i - 1]));
    if (!(hi - lo > 0) || gap <= max_gap_fraction * (hi - lo)) continue;
    std::string at;
    for (double v : r) at += fmt::format("{}{:+.1f}", at.empty() ? "" : ", ", v);
    const std::string which = state == "warm" ? "dry" : sessions > 1 ? fmt::format("coolant (session {})", session) : "coolant";
    out.push_back(fmt::format("{} {} warm-up: tests at nut {} °C vs cold; {:.1f} of its {:.1f} °C rise ({:.0f} %) "
                              "lie between two of them, untested",
                              axis, which, at, gap, hi - lo, 100 * gap / (hi - lo)));
  }
  return out;
}

namespace {

std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "";
  const double scale = std::pow(10.0, digits);
  return FormatShortest(std::round(v * scale) / scale);
}

class Campaign {
 public:
  Campaign(const MachineDescription& machine, const CampaignOptions& o)
      : o_(o), vm_(machine, o.seed), laser_(o.laser, o.seed * 7919 + 17) {
    // (warm measurements use o.warm_runs; see MeasureAndWrite)
    for (std::size_t i = 0; i < vm_.ChannelCount(); ++i) sensor_names_.push_back(vm_.ChannelName(i));
    if (o.axes.empty()) {
      for (std::size_t i = 0; i < vm_.AxisCount(); ++i) axes_.push_back(i);
    } else {
      for (const auto& name : o.axes) {
        const int i = machine.AxisIndex(name);
        if (i < 0) throw InputError("--axes", 0, name, "the machine has no axis '" + name + "'");
        if (std::find(axes_.begin(), axes_.end(), static_cast<std::size_t>(i)) == axes_.end()) axes_.push_back(i);
      }
    }
    midnight_unix_ = std::floor(vm_.UnixTimeS() / 86400.0) * 86400.0;
    log_ = MachineLogHeader(vm_);
  }

  CampaignSummary Run() {
    const auto wall0 = std::chrono::steady_clock::now();
    std::filesystem::create_directories(o_.out_dir);
    for (std::size_t k = 0; k < axes_.size(); ++k) ColdAndWarm(axes_[k], static_cast<int>(k));
    int last_day = static_cast<int>(axes_.size()) - 1;
    if (o_.coolant_visit != CampaignOptions::CoolantVisit::kAfterSeasons) last_day = CoolantSessions(last_day);
    for (int offset : o_.ambient_day_offsets) {
      for (double hour : o_.ambient_hours) {
        // An hour the day's earlier measurements ran past falls on the next day (GoTo): said, the
        // fit still gets the state, but not on the day asked for.
        if (!GoTo(offset, hour))
          Progress(fmt::format("ambient at {:.1f} h of day {}: the earlier measurements ran past it, measuring a day later",
                               hour, offset));
        for (std::size_t a : axes_) {
          StartSession();
          Setup(a);
          MeasureAndWrite(a, "ambient");
          EndSession();
        }
      }
      last_day = std::max(last_day, offset);
    }
    if (o_.coolant_visit != CampaignOptions::CoolantVisit::kFirstVisit) CoolantSessions(last_day);
    WriteTextFile((std::filesystem::path(o_.out_dir) / measure::kCampaignLogFile).string(), log_);
    WriteManifest();
    summary_.machine_time_s = vm_.TimeS();
    summary_.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    return summary_;
  }

 private:
  void Progress(const std::string& line) {
    if (o_.progress) o_.progress(fmt::format("[{} t={:.2f} h] {}", vm_.IsoTime(), vm_.TimeS() / 3600.0, line));
  }

  // Day `day` after the start date at `hour`; if that is past, the next day. False when it was.
  bool GoTo(int day, double hour) {
    double t = midnight_unix_ + day * 86400.0 + hour * 3600.0 - vm_.UnixTimeS() + vm_.TimeS();
    bool as_asked = true;
    while (t < vm_.TimeS() - 1e-6) t += 86400.0, as_asked = false;
    EndSession();
    vm_.IdleUntil(t);
    return as_asked;
  }

  void StartSession() {
    vm_.SetLogger(o_.log_interval_s, [this](const VirtualMachine& vm) { LogRow(vm); });
  }
  void EndSession() { vm_.SetLogger(0, nullptr); }

  void LogRow(const VirtualMachine& vm) { log_ += MachineLogRow(vm); }

  std::string NutSensor(std::size_t axis) const { return LowerAscii(vm_.AxisName(axis)) + "_nut"; }

  // Nut temperature as the engineer watches it: the sensor if there is one
  // (mean of the last minute), else the thermal node.
  double NutNow(std::size_t axis) {
    const int i = vm_.SensorIndex(NutSensor(axis));
    const auto r = i >= 0 ? vm_.sensor(i).Latest() : hw::RawTemperature{};
    if (i < 0 || r.hardware_fault) return vm_.NodeTemperatureC(NutSensor(axis));
    return r.temp_c;
  }

  void Setup(std::size_t axis) {
    laser_.Setup(vm_, axis, vm_.description().axes[axis].reference_mm);
  }

  static double MeanColumn(const measure::Measurement& m, const std::string& sensor) {
    const auto idx = m.SensorIndex(sensor);
    if (!idx) return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    int n = 0;
    for (const auto& p : m.points)
      if (!std::isnan(p.temperatures_c[*idx])) {
        sum += p.temperatures_c[*idx];
        ++n;
      }
    return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
  }

  measure::Measurement MeasureAndWrite(std::size_t axis, const std::string& state) {
    const std::string axis_name = vm_.AxisName(axis);
    const int seq = ++sequence_[axis_name + "/" + state];
    const int file_no = ++file_count_[axis_name];
    const std::string file = fmt::format("{}_{:02}_{}{}.csv", axis_name, file_no, state,
                                         state == "cold" ? std::string() : fmt::format("_{:02}", seq));
    Progress(fmt::format("measuring {} ({} #{}, coolant {})", axis_name, state, seq, CoolantStateName(vm_.coolant())));
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
    CampaignFile f;
    f.file = file;
    f.axis = axis_name;
    f.state = state;
    f.coolant = std::string(CoolantStateName(vm_.coolant()));
    f.sequence = seq;
    f.start_time_s = vm_.TimeS();
    f.start_date = vm_.IsoTime();
    const bool short_test = state == "warm" || state == "cooldown" || (state == "coolant" && seq > 1);
    auto m = laser_.Measure(vm_, short_test ? o_.warm_runs : o_.laser.runs,
                            {{"state", state},
                                  {"sequence", std::to_string(seq)},
                                  {"campaign_time_s", Fixed(vm_.TimeS(), 1)}});
    f.end_time_s = vm_.TimeS();
    const double nut = MeanColumn(m, NutSensor(axis));
    if (state == "cold" || !cold_nut_.count(axis_name)) cold_nut_[axis_name] = nut;
    f.nut_rise_c = nut - cold_nut_[axis_name];
    f.coolant_session = in_coolant_session_ ? coolant_session_ : 0;
    m.SetMeta("nut_rise_c", Fixed(f.nut_rise_c, 3));
    measure::WriteMeasurementCsv(m, (std::filesystem::path(o_.out_dir) / file).string());
    std::map<std::string, double> means;
    for (const auto& s : sensor_names_) means[s] = MeanColumn(m, s);
    means_.push_back(means);
    summary_.files.push_back(f);
    Progress(fmt::format("wrote {} (nut {:+.2f} °C vs cold, {:.0f} s)", file, f.nut_rise_c, f.end_time_s - f.start_time_s));
    return m;
  }

  void StartWarmUpMotion() {
    // Seed 000: X, Y, Z together at 2000–4000 mm/min; strokes alternate the two feeds.
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) {
      const double travel = vm_.description().axes[i].travel_mm;
      const double margin = std::min(10.0, travel * 0.02);
      vm_.CommandReciprocate(i, margin, travel - margin, o_.warmup_feed_low_mm_min, 1.0, o_.warmup_feed_high_mm_min);
    }
  }

  // Warm-up with a measurement each time the nut rose another nut_step_c
  // above `nut0`, until saturation, the time cap or `max_measurements`.
  void WarmUp(std::size_t axis, double nut0, const std::string& state, int max_measurements) {
    if (max_measurements <= 0) return;
    const double chunk_s = 10;
    WarmUpRule rule;
    rule.nut_step_c = o_.nut_step_c;
    rule.nut_step_growth = o_.nut_step_growth;
    rule.max_measurements = max_measurements;
    rule.saturation_window_s = o_.saturation_window_min * 60;
    rule.saturation_rise_c = o_.saturation_rise_c;
    std::vector<double> history;  // nut readings every chunk of warm-up time since the last test
    std::deque<double> minute;    // last minute, to average the sensor noise
    double next = NextTestRise(rule, {}, 0, 0);
    double warm_s = 0, warm_at_test_s = 0, last_test_s = 0;
    int taken = 0;
    WarmUpCurve curve;  // (warm-up seconds, nut rise), never reset
    StartWarmUpMotion();
    Progress(fmt::format("warm-up ({} coolant), nut start {:.2f} °C", CoolantStateName(vm_.coolant()), nut0));
    // Threshold measurements up to max_measurements − 1; the last one is
    // always kept for the saturated state (or the time cap).
    while (true) {
      vm_.Advance(chunk_s);
      warm_s += chunk_s;
      minute.push_back(NutNow(axis));
      if (minute.size() > 6) minute.pop_front();
      double nut = 0;
      for (double v : minute) nut += v;
      nut /= static_cast<double>(minute.size());
      history.push_back(nut);
      const double rise = nut - nut0;
      curve.emplace_back(warm_s, rise);
      // Settled, not still falling: a session over a warm machine first sees the nut drawn down to the coolant.
      const bool saturated = WarmUpSaturated(rule, history, chunk_s);
      const bool timeout = warm_s >= o_.max_warmup_hours * 3600;
      if (saturated || timeout) {
        Progress(saturated ? "thermal saturation reached" : "warm-up time cap reached");
        MeasureAndWrite(axis, state);
        ++taken;
        break;
      }
      const bool machined_enough = state != "warm" || warm_s - warm_at_test_s >= o_.min_warmup_per_test * last_test_s;
      if (std::abs(rise) >= next && machined_enough && ThresholdTestAllowed(rule, taken)) {  // up, or down to the coolant
        const double t0 = vm_.TimeS();
        MeasureAndWrite(axis, state);
        last_test_s = vm_.TimeS() - t0;
        warm_at_test_s = warm_s;
        ++taken;
        next = NextTestRise(rule, curve, rise, taken);
        StartWarmUpMotion();
        history.clear();  // the measurement interrupted the warm-up: judge saturation afresh
        minute.clear();
      }
    }
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
  }

  // The axes stop; every cooldown_step_c the nut sensor falls, a measurement (labelled `state`).
  void CoolDown(std::size_t axis, const char* state) {
    if (o_.cooldown_measurements <= 0) return;
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
    Progress("cool-down: axes stopped");
    double ref = NutNow(axis);
    double waited = 0;
    std::deque<double> minute;
    int taken = 0;
    for (; taken < o_.cooldown_measurements && waited < o_.max_cooldown_hours * 3600;) {
      vm_.Advance(10);
      waited += 10;
      minute.push_back(NutNow(axis));
      if (minute.size() > 6) minute.pop_front();
      double nut = 0;
      for (double v : minute) nut += v;
      nut /= static_cast<double>(minute.size());
      if (ref - nut >= o_.cooldown_step_c) {
        MeasureAndWrite(axis, state);
        ++taken;
        for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
        ref = nut;  // the test's own motion warmed it a little: count from before it
        minute.clear();
      }
    }
    if (taken < o_.cooldown_measurements)  // said, not silent: the fit gets fewer states of this kind
      Progress(fmt::format("{}: {} of {} measurements — the nut sensor fell less than {:.2f} °C in {:.1f} h", state, taken,
                           o_.cooldown_measurements, o_.cooldown_step_c, o_.max_cooldown_hours));
  }

  // Every coolant session, each axis on its own day after `last_day`; returns the last day used.
  int CoolantSessions(int last_day) {
    if (!o_.coolant_session || o_.max_coolant_measurements <= 0) return last_day;
    int day = last_day;
    in_coolant_session_ = true;
    for (double prewarm_h : o_.coolant_prewarm_h) {
      ++coolant_session_;
      for (std::size_t a : axes_) CoolantSession(a, ++day, prewarm_h);
    }
    in_coolant_session_ = false;
    return day;
  }

  // Flood on (after `prewarm_h` of dry warm-up machining), a test at once, a warm-up under the
  // coolant, then the stop under it.
  void CoolantSession(std::size_t axis, int day, double prewarm_h) {
    GoTo(day, 7.0);
    StartSession();
    if (prewarm_h > 0) {
      Progress(fmt::format("dry machining {:.1f} h before the coolant session", prewarm_h));
      StartWarmUpMotion();
      vm_.Advance(prewarm_h * 3600);
      for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
    }
    vm_.SetCoolant(o_.coolant_state);
    Setup(axis);
    const double nut0 = MeanColumn(MeasureAndWrite(axis, "coolant"), NutSensor(axis));
    WarmUp(axis, nut0, "coolant", o_.max_coolant_measurements - 1);
    // The coolant still running over an axis at rest (a tool change, a measuring cycle, the
    // operator's break): the screw is drawn to the coolant, not to the nut's reading — a state
    // the working day has and the warm-up alone never shows the fit.
    if (o_.coolant_rest) CoolDown(axis, "coolant_rest");
    EndSession();
  }

  void ColdAndWarm(std::size_t axis, int k) {
    GoTo(k, 7.0);
    StartSession();
    Setup(axis);
    const auto cold = MeasureAndWrite(axis, "cold");
    WarmUp(axis, MeanColumn(cold, NutSensor(axis)), "warm", o_.max_warm_measurements);
    CoolDown(axis, "cooldown");
    EndSession();
  }

  void WriteManifest() {
    measure::CampaignManifest m;
    m.machine = vm_.description().name;
    m.machine_file = vm_.description().source;
    m.seed = o_.seed;
    m.start_date = vm_.description().start_iso;
    m.sensors = sensor_names_;
    for (const auto& s : vm_.description().sensors)
      if (!s.location.empty() && s.location != s.name) m.sensor_locations[s.name] = s.location;
    for (std::size_t i = 0; i < summary_.files.size(); ++i) {
      const auto& f = summary_.files[i];
      measure::CampaignEntry e;
      e.file = f.file;
      e.axis = f.axis;
      e.state = f.state;
      e.coolant = f.coolant;
      e.sequence = f.sequence;
      e.start_date = f.start_date;
      e.start_time_s = f.start_time_s;
      e.end_time_s = f.end_time_s;
      e.nut_rise_c = f.nut_rise_c;
      e.coolant_session = f.coolant_session;
      for (const auto& s : sensor_names_) e.mean_temperatures_c.emplace_back(s, means_[i].at(s));
      m.measurements.push_back(std::move(e));
    }
    measure::WriteCampaignManifest(m, (std::filesystem::path(o_.out_dir) / measure::kCampaignManifestFile).string());
  }

  CampaignOptions o_;
  VirtualMachine vm_;
  LaserInterferometer laser_;
  std::vector<std::size_t> axes_;
  std::vector<std::string> sensor_names_;
  double midnight_unix_ = 0;
  std::string log_;
  std::map<std::string, int> sequence_, file_count_;
  std::map<std::string, double> cold_nut_;
  int coolant_session_ = 0;  // the session being measured (CampaignFile::coolant_session), counted over the campaign
  bool in_coolant_session_ = false;
  std::vector<std::map<std::string, double>> means_;
  CampaignSummary summary_;
};

}  // namespace

CampaignSummary RunCampaign(const MachineDescription& machine, const CampaignOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("campaign options: " + why);
  Campaign c(machine, options);
  return c.Run();
}

}  // namespace trueaxis::sim
