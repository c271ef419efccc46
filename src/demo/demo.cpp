#include "trueaxis/demo/demo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "trueaxis/core/duration_text.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/model/compensation_bound.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/station/cycle_log.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/sim/ambient_profile.hpp"
#include "trueaxis/sim/campaign.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/station/machine_connection.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/machine_log.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/virtual_machine.hpp"
#include "demo_report.hpp"

namespace trueaxis::demo {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

bool DemoOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string m) {
    if (why) *why = std::move(m);
    return false;
  };
  if (machine_file.empty()) return fail("machine_file is empty");
  if (out_dir.empty()) return fail("out_dir is empty");
  if (!(period_s >= 0.001 && period_s <= 1)) return fail(fmt::format("period_s must be in [0.001, 1] s, got {}", period_s));
  if (geometric != "auto" && geometric != "polynomial" && geometric != "table")
    return fail("geometric must be auto, polynomial or table, got '" + geometric + "'");
  if (day_offset < 1 || other_day_offset <= day_offset)
    return fail("day_offset must be >= 1 and other_day_offset > day_offset");
  if (motion_heat != "auto" && motion_heat != "on" && motion_heat != "off")
    return fail("motion_heat must be auto, on or off, got '" + motion_heat + "'");
  if (key_offsets != "auto" && key_offsets != "on" && key_offsets != "off")
    return fail("key_offsets must be auto, on or off, got '" + key_offsets + "'");
  {  // the fit's own check of the ridge, before anything runs
    model::FitOptions f;
    f.secondary_key_ridge = secondary_key_ridge;
    if (!f.IsValid(why)) return false;
  }
  if (!ambient_hours.empty() || ambient_day_offsets) {  // the campaign's own check, before the campaign runs
    sim::CampaignOptions c;
    c.out_dir = out_dir;
    if (!ambient_hours.empty()) c.ambient_hours = ambient_hours;
    if (ambient_day_offsets) c.ambient_day_offsets = *ambient_day_offsets;
    if (!c.IsValid(why)) return false;
  }
  return compensator.IsValid(why);
}

std::string DemoResult::DaySpans() const {
  // "2026-04-01T07:00:00" → date "2026-04-01", time "07:00".
  auto span = [](double from_s, double to_s) {
    const std::string a = sim::FormatIsoTime(from_s), b = sim::FormatIsoTime(to_s);
    const std::string to = a.substr(0, 10) == b.substr(0, 10) ? b.substr(11, 5) : b.substr(0, 10) + " " + b.substr(11, 5);
    return fmt::format("{} {}–{} ({})", a.substr(0, 10), a.substr(11, 5), to, FormatDuration(to_s - from_s));
  };
  return span(day_start_s, day_end_s) + " and " + span(other_day_start_s, other_day_end_s);
}

bool StateResult::UnderMustLine() const {
  const double a_off = eval_off.axis.A_um, a_on = eval_on.axis.A_um;
  const double r_off = eval_off.axis.R_um, r_on = eval_on.axis.R_um;
  return a_on <= std::max(0.2 * a_off, 2 * r_on) && a_on < a_off && r_on <= 2 * r_off + 2;
}

bool StateResult::AtGoal() const {
  return eval_on.axis.A_um <= std::max(0.1 * eval_off.axis.A_um, 1.3 * eval_on.axis.R_um);
}

std::string DemoResult::BriefReport() const {
  std::string s = fmt::format("{:<14} {:<4} {:>10} {:>12} {:>12} {:>8}  {}\n", "state", "axis", "nut rise", "A off (µm)",
                              "A on (µm)", "factor", "verdict");
  int must = 0, goal = 0;
  for (const auto& r : states) {
    must += r.UnderMustLine();
    goal += r.AtGoal();
    s += fmt::format("{:<14} {:<4} {:>11} {:>12.1f} {:>12.1f} {:>7.1f}×  {}\n", r.state, r.axis,
                     std::isnan(r.nut_rise_c) ? std::string("no reading") : fmt::format("{:+.1f} °C", r.nut_rise_c),
                     r.eval_off.axis.A_um, r.eval_on.axis.A_um, r.Factor(),
                     r.AtGoal() ? "goal" : r.UnderMustLine() ? "must" : "MISSED the must line");
  }
  s += fmt::format("{} of {} tests under the must line, {} at the goal (docs/concepts.md)\n", must, states.size(), goal);
  s += fmt::format("days: {}; compensated {} of machine time\n", DaySpans(), FormatDuration(compensated_s));
  s += fmt::format("loop: {}\nwall time {:.1f} s (campaign {:.1f} s, fit {:.1f} s, day {:.1f} s)\n",
                   loop_stats.BriefReport(), wall_s, campaign_wall_s, fit_wall_s, day_wall_s);
  std::string bounds;
  for (std::size_t i = 0; i < machine_axes.size() && i < bound_um.size(); ++i) {
    const std::uint64_t n = i < clamped_cycles.size() ? clamped_cycles[i] : 0;
    const std::uint64_t e = i < extrapolated_cycles.size() ? extrapolated_cycles[i] : 0;
    const std::uint64_t room = i < room_extrapolated_cycles.size() ? room_extrapolated_cycles[i] : 0;
    bounds += fmt::format("{}{} ±{:g} µm{}{}{}", bounds.empty() ? "" : ", ", machine_axes[i], bound_um[i],
                          n ? fmt::format(" (SATURATED in {} cycles)", n) : "",
                          e ? fmt::format(" (held at the model's fitted envelope in {} cycles)", e) : "",
                          room ? fmt::format(" (room outside the fitted range in {} cycles)", room) : "");
  }
  if (!bounds.empty()) s += "bounds: " + bounds + "\n";
  for (const auto& f : sensor_faults) s += "sensor fault: " + f + "\n";
  std::string reduced, lost;
  for (std::size_t i = 0; i < machine_axes.size(); ++i) {
    const std::uint64_t r = i < fallback_model_cycles.size() ? fallback_model_cycles[i] : 0;
    const std::uint64_t a = i < averaged_fallback_cycles.size() ? averaged_fallback_cycles[i] : 0;
    const std::uint64_t g = i < sensor_fallback_cycles.size() ? sensor_fallback_cycles[i] : 0;
    if (r)
      reduced += fmt::format("{}{} {} cycles{}", reduced.empty() ? "" : ", ", machine_axes[i], r,
                             a ? fmt::format(" ({} of them the mean of the fallbacks replacing the lost sensor)", a) : "");
    if (g) lost += fmt::format("{}{} {} cycles", lost.empty() ? "" : ", ", machine_axes[i], g);
  }
  if (!reduced.empty() || !lost.empty())
    s += fmt::format("sensor lost (alarm sensor_fallback): on a fallback model {}; without the thermal part {}\n",
                     reduced.empty() ? "never" : reduced, lost.empty() ? "never" : lost);
  return s;
}

namespace {

std::string Lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

double MeanSensor(const measure::Measurement& m, const std::string& name) {
  const auto idx = m.SensorIndex(name);
  if (!idx) return std::nan("");
  double sum = 0;
  int n = 0;
  for (const auto& p : m.points)
    if (std::isfinite(p.temperatures_c[*idx])) {
      sum += p.temperatures_c[*idx];
      ++n;
    }
  return n ? sum / n : std::nan("");
}

// Samples the day once per minute of machine time, and writes those cycles to the installation's
// record (station::CycleLog: the history database, as `run` writes it).
class DayObserver : public runtime::CycleObserver {
 public:
  DayObserver(sim::VirtualMachine& vm, DemoResult& result, station::CycleLog* log) : vm_(vm), result_(result), log_(log) {}
  void OnCycle(const runtime::CycleStatus& s) override {
    alarms_ |= s.alarms;
    ++result_.day_cycles;
    if (result_.clamped_cycles.size() < s.axes.size()) result_.clamped_cycles.resize(s.axes.size(), 0);
    if (result_.extrapolated_cycles.size() < s.axes.size()) result_.extrapolated_cycles.resize(s.axes.size(), 0);
    if (result_.room_extrapolated_cycles.size() < s.axes.size()) result_.room_extrapolated_cycles.resize(s.axes.size(), 0);
    if (result_.sensor_fallback_cycles.size() < s.axes.size()) result_.sensor_fallback_cycles.resize(s.axes.size(), 0);
    if (result_.fallback_model_cycles.size() < s.axes.size()) result_.fallback_model_cycles.resize(s.axes.size(), 0);
    if (result_.averaged_fallback_cycles.size() < s.axes.size()) result_.averaged_fallback_cycles.resize(s.axes.size(), 0);
    for (std::size_t i = 0; i < s.axes.size(); ++i) {
      if ((s.alarms & runtime::kAlarmSensorFallback) && s.axes[i].enabled && !s.axes[i].thermal_used) ++result_.sensor_fallback_cycles[i];
      if (s.axes[i].fallback_model >= 0) ++result_.fallback_model_cycles[i];
      if (s.axes[i].fallbacks_averaged > 1) ++result_.averaged_fallback_cycles[i];
      if (s.axes[i].clamped) ++result_.clamped_cycles[i];
      if (s.axes[i].prediction.tan_beta_limited) ++result_.extrapolated_cycles[i];
      if (s.axes[i].prediction.ambient_extrapolated) ++result_.room_extrapolated_cycles[i];
    }
    if (s.alarms != last_alarms_) {
      ++result_.alarm_changes;
      if (result_.alarm_log.size() < 200)
        result_.alarm_log.push_back(fmt::format("{} {}", vm_.IsoTime(), s.alarms ? runtime::AlarmNames(s.alarms) : "cleared"));
      tally_.Update(s.alarms, vm_.UnixTimeS());
    }
    last_alarms_ = s.alarms;
    last_cycle_unix_s_ = vm_.UnixTimeS();
    const double t = vm_.TimeS();
    if (t < next_sample_s_) return;
    next_sample_s_ = t + 60;
    DaySample d;
    d.time_h = (vm_.TimeS() - day_start_s_) / 3600.0;
    for (const auto& c : s.channels) d.temp_c.push_back(c.value_c);
    for (const auto& a : s.axes) d.correction_um.push_back(a.output_um);
    d.coolant = s.coolant;
    d.alarms = s.alarms;
    d.other_day = other_day_;
    result_.day.push_back(std::move(d));
    if (log_) {
      runtime::FillRecord(s, record_);
      record_.time_s = vm_.UnixTimeS();
      log_->Log(record_);
    }
  }
  void SetDayStart(double t_s, bool other_day) {
    // The machine stood switched off since the last cycle: an alarm active then ended there.
    if (last_cycle_unix_s_ > 0) tally_.Pause(last_cycle_unix_s_);
    last_alarms_ = 0;
    day_start_s_ = t_s;
    next_sample_s_ = 0;
    other_day_ = other_day;
  }
  std::uint32_t alarms() const { return alarms_; }
  std::vector<AlarmSummaryRow> AlarmSummary() const { return tally_.Rows(last_cycle_unix_s_); }

 private:
  AlarmTally tally_;
  double last_cycle_unix_s_ = 0;
  sim::VirtualMachine& vm_;
  DemoResult& result_;
  station::CycleLog* log_;
  runtime::CycleRecord record_;
  double day_start_s_ = 0, next_sample_s_ = 0;
  bool other_day_ = false;
  std::uint32_t alarms_ = 0, last_alarms_ = 0;
};

// Probes at one place (the machine file's sensors sharing a `location`, e.g. two on one nut):
// the temperature pipeline checks them against each other (a neighbour group; when they disagree
// by more than max_disagreement_c both are lost) and the fit's fallbacks do without all of them.
std::vector<std::vector<std::string>> RedundantProbes(const sim::MachineDescription& md) {
  std::map<std::string, std::vector<std::string>> by_location;
  for (const auto& sd : md.sensors) by_location[sd.location].push_back(sd.name);
  std::vector<std::vector<std::string>> groups;
  for (auto& [where, names] : by_location)
    if (names.size() >= 2) groups.push_back(names);
  return groups;
}

class WorkingDay {
 public:
  WorkingDay(const sim::MachineDescription& md, const DemoOptions& o, const sim::LaserOptions& laser,
             std::shared_ptr<const model::CompositeModel> model, const std::string& model_label, DemoResult& result,
             const station::HistoryConfig& history)
      : o_(o),
        result_(result),
        vm_(md, o.seed + 1000),  // another run of the same machine: the day is held out from the fit
        laser_(laser, o.seed * 7919 + 4242) {
    for (std::size_t i = 0; i < vm_.ChannelCount(); ++i) result_.channel_names.push_back(vm_.ChannelName(i));
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) all_axes_.push_back(vm_.AxisName(i));
    day_faults_ = md.day_faults;
    result_.machine_axes = all_axes_;
    // Axes without a model (not calibrated in this run) stay switched off.
    std::vector<runtime::AxisInterface> interfaces;
    for (const auto& name : all_axes_) {
      runtime::AxisInterface a;
      a.axis = name;
      const auto* am = model->FindAxis(name);
      a.enabled = am != nullptr;
      if (am && o.derive_bounds) {
        model::CompensationBoundOptions bo;
        bo.controller_limit_um = o.controller_limit_um;
        const auto b = model::DeriveCompensationBound(*am, bo);
        a.max_correction_um = b.bound_um;
        result_.bound_source.push_back("from the model: " + b.BriefReport());
      } else {
        result_.bound_source.push_back(am ? "fixed (--fixed-bound)" : "axis not compensated");
      }
      result_.bound_um.push_back(std::isnan(a.max_correction_um) ? o.compensator.shaper.max_correction_um
                                                                 : a.max_correction_um);
      interfaces.push_back(a);
    }
    hw::CncLink* link = &vm_;
    hw::TemperatureSource* source = &vm_;
    result_.interface_used = "in-process CncLink / TemperatureSource (sim::VirtualMachine)";
    if (o.modbus) {
      StartModbus();
      link = cnc_client_.get();
      source = temp_client_.get();
    }
    // The installation: the one temperature pipeline (timed by the machine's clock), the compensator.
    station::InstallationConfig rc;
    rc.source = "demo";
    rc.compensator = o.compensator;
    rc.axes = interfaces;
    rc.signal_processing = o.signal_processing;  // --raw-temperatures: judged all the same, no filter
    rc.redundant_groups = RedundantProbes(md);
    result_.interface_used += o.signal_processing ? "; temperatures through signal::MonitoredTemperatureSource"
                                                  : "; temperatures judged unfiltered by signal::MonitoredTemperatureSource";
    installation_ = std::make_unique<station::Installation>(rc, *link, *source, [this] { return vm_.TimeS(); }, "");
    comp_ = &installation_->compensator();
    // Its record: the history database; the day's records carry their Unix time (time 0 = 1970).
    if (!history.db.empty()) installation_->OpenLog(history, 0);
    observer_ = std::make_unique<DayObserver>(vm_, result_, installation_->log());
    runner_ = std::make_unique<runtime::LoopRunner>(*comp_, *link, installation_->temperatures(), runtime::LoopOptions{o.period_s},
                                                    observer_.get());
    advance_ = [this](double dt) { vm_.Advance(dt); };
    const std::string revision = std::to_string(model->revision);
    installation_->Publish(station::PublishedModel{revision, std::move(model), {}}, model_label);
  }

  // The model in force is recorded (history: `note`, file SHA-256 `model_sha`) when the day starts.
  void Run(const std::vector<std::string>& axes, const std::string& model_sha, const std::string& note) {
    const bool fast = o_.fast;  // fast: fewer states measured (the machine time is cheap)
    // The working day starts at 07:00, `day_offset` days after the campaign's first day.
    IdleUntil(o_.day_offset * 86400.0);
    observer_->SetDayStart(vm_.TimeS(), false);
    result_.day_start_s = vm_.UnixTimeS();
    // The day's machine log, as the campaign's temperature_log.csv: motion and temperatures.
    machine_log_ = sim::MachineLogHeader(vm_);
    vm_.SetLogger(30, [this](const sim::VirtualMachine& vm) { machine_log_ += sim::MachineLogRow(vm); });
    ScheduleDayFaults();
    if (station::CycleLog* log = installation_->log())
      log->ModelPublished(installation_->model(), model_sha, note, note, vm_.UnixTimeS());
    Progress(fmt::format("working day {}: machine cold, compensator running every {:.0f} ms", vm_.IsoTime(), o_.period_s * 1000));
    Step(60);
    MeasureState("cold", axes);
    Machining(3.0, CoolantState::kOff);
    MeasureState("warm", axes);
    Machining(2.5, CoolantState::kFlood);
    MeasureState("warm+coolant", axes);
    Machining(1.5, CoolantState::kOff);
    if (!fast) MeasureState("afternoon", axes);
    StopAll();
    vm_.SetCoolant(CoolantState::kOff);
    result_.day_end_s = vm_.UnixTimeS();
    // Another day: the machine soaked at another season's air, mid-morning.
    const double day_h = (vm_.TimeS() - o_.day_offset * 86400.0) / 3600.0;
    for (const auto& f : day_faults_) {  // in the months between: the sensor was replaced
      vm_.SetSensorFault(f.sensor, sim::SensorFault{});
      Progress(fmt::format("sensor {} replaced since the working day", f.sensor));
    }
    IdleUntil(o_.other_day_offset * 86400.0 + 3 * 3600.0);
    observer_->SetDayStart(vm_.TimeS() - day_h * 3600.0 - 3600.0, true);  // plotted after a 1 h gap
    result_.other_day_start_s = vm_.UnixTimeS();
    Progress(fmt::format("another day {}: machine soaked at {:.1f} °C air", vm_.IsoTime(), vm_.AmbientC()));
    Step(60);
    MeasureState("other day", axes);
    result_.other_day_end_s = vm_.UnixTimeS();
    result_.loop_stats = runner_->Stats();
    result_.compensated_s = static_cast<double>(result_.loop_stats.cycles) * o_.period_s;
    result_.period_s = o_.period_s;
    result_.alarms_seen = observer_->alarms();
    result_.alarm_summary = observer_->AlarmSummary();
    vm_.SetLogger(0, nullptr);
    WriteTextFile((std::filesystem::path(result_.out_dir) / "day" / "machine_log.csv").string(), machine_log_);
  }

  void CloseLog() {
    if (station::CycleLog* log = installation_->log()) log->Close();
  }

  ~WorkingDay() {
    if (vm_lock_.owns_lock()) vm_lock_.unlock();
    if (server_) server_->Stop();
  }


 private:
  // The machine file's [[day_fault]]s, at their hours after the day's start (the machine applies
  // each on its thermal grid; the compensator finds out from the readings, as on a real machine).
  void ScheduleDayFaults() {
    for (const auto& f : day_faults_) {
      sim::SensorFault fault;
      fault.kind = *sim::ParseSensorFaultKind(f.kind);  // checked by the machine-file reader
      const double at_s = vm_.TimeS() + f.at_h * 3600.0;
      vm_.ScheduleSensorFault(f.sensor, fault, at_s);
      result_.sensor_faults.push_back(fmt::format("{} {} at {} ({:g} h into the working day; [[day_fault]] in the machine file)",
                                                  f.sensor, f.kind, sim::FormatIsoTime(vm_.UnixTimeS() + f.at_h * 3600.0), f.at_h));
      Progress("sensor fault scheduled: " + result_.sensor_faults.back());
    }
  }

  void StartModbus() {
    drivers::ModbusMachineServerOptions so;
    so.machine_period_s = 0.0002;
    std::string error;
    int port = o_.modbus_port;
    for (int attempt = 0; attempt < 50; ++attempt) {
      so.port = o_.modbus_port ? o_.modbus_port : 15020 + attempt;
      server_ = std::make_unique<drivers::ModbusMachineServer>(&vm_, &vm_, so);
      server_->ShareMachineWith(&vm_mutex_);  // the demo thread moves the machine between cycles
      if (server_->Start(&error)) {
        port = so.port;
        break;
      }
      server_.reset();
      if (o_.modbus_port) break;
    }
    if (!server_) throw std::runtime_error("demo: cannot start the MODBUS terminal on 127.0.0.1: " + error);
    station::ModbusConfig mc;
    mc.port = port;
    mc.response_timeout_s = 0.5;
    mc.cnc_unit_id = so.pmc_unit_id;
    mc.first_rtd_unit_id = so.first_rtd_unit_id;
    mc.axis_names = all_axes_;
    mc.channel_names = result_.channel_names;
    auto clients = station::MakeModbusClients(mc, "demo", 2.0);
    cnc_client_ = std::move(clients.cnc);
    temp_client_ = std::move(clients.temperatures);
    std::string why;  // hw lifecycle: options checked by MakeModbusClients; activate = connect
    cnc_client_->Activate(&why);
    temp_client_->Activate(&why);
    result_.interface_used = fmt::format("MODBUS TCP 127.0.0.1:{} (PMC window unit {}, {} ADAM-6015 modules)", port,
                                         so.pmc_unit_id, drivers::RtdModuleUnitIds(mc.first_rtd_unit_id, mc.channel_names.size()).size());
    // From here on the demo thread holds the machine except while a cycle
    // talks to the terminal (whose machine thread then reads and writes it).
    vm_lock_ = std::unique_lock<std::mutex>(vm_mutex_);
  }

  // `n` compensation cycles, the machine advancing one period before each.
  void Cycles(std::uint64_t n) {
    if (!o_.modbus) {
      runner_->StepSimulated(n, advance_);
      return;
    }
    for (std::uint64_t i = 0; i < n; ++i) {
      vm_.Advance(o_.period_s);
      vm_lock_.unlock();
      // Lockstep: let the terminal's machine thread take (at least) one full
      // exchange with the advanced machine before the cycle reads the window.
      const auto e0 = server_->Stats().exchanges;
      while (server_->Stats().exchanges < e0 + 2) std::this_thread::yield();
      runner_->StepSimulated(1, nullptr);
      vm_lock_.lock();
    }
  }

  void Progress(const std::string& s) {
    if (o_.progress) o_.progress(fmt::format("[demo {} t={:.2f} h] {}", vm_.IsoTime(), vm_.TimeS() / 3600.0, s));
  }
  void Step(double seconds) {
    Cycles(static_cast<std::uint64_t>(std::llround(seconds / o_.period_s)));
  }
  // The machine stands switched off until t_s; the compensator's clock jumps with it.
  void IdleUntil(double t_s) {
    const double before = vm_.TimeS();
    vm_.IdleUntil(t_s);
    runner_->PauseSimulated(vm_.TimeS() - before);
  }
  void StopAll() {
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) vm_.CommandStop(i);
  }
  void MoveAndWait(std::size_t axis, double target_mm, double feed_mm_min) {
    vm_.CommandMove(axis, target_mm, feed_mm_min);
    for (int guard = 0; vm_.IsMoving(axis) && guard < 10'000'000; ++guard) Cycles(1);
  }
  void SetCompensation(bool on) {
    comp_->SetEnabled(on);
    // Wait for the ramp (at most max_correction / max_step cycles, plus margin).
    const auto& so = o_.compensator.shaper;
    double largest_bound = so.max_correction_um;
    for (double b : result_.bound_um) largest_bound = std::max(largest_bound, b);
    const double ramp_s = (largest_bound / so.max_step_um + 10) * o_.period_s;
    for (double waited = 0; waited < ramp_s; waited += o_.period_s) {
      Cycles(1);
      if (!on) {
        bool zero = true;
        for (const auto& a : comp_->LastStatus().axes) zero = zero && a.output_um == 0;
        if (zero) break;
      }
    }
  }
  void Machining(double hours, CoolantState coolant) {
    vm_.SetCoolant(coolant);
    Progress(fmt::format("machining {:.1f} h, coolant {}", hours, CoolantStateName(coolant)));
    for (std::size_t i = 0; i < vm_.AxisCount(); ++i) {
      const double travel = vm_.description().axes[i].travel_mm;
      vm_.CommandReciprocate(i, 0.1 * travel, 0.9 * travel, 3000, 0.7, 4000);
    }
    for (double h = 0; h < hours - 1e-9; h += 0.5) Step(std::min(0.5, hours - h) * 3600);
    StopAll();
  }

  // The laser test of seed 000 §5 / ISO 230-2, with the compensator cycling
  // throughout (moves and dwells advance the machine one period per cycle).
  measure::Measurement Measure(std::size_t axis, const std::string& state, bool compensated) {
    const auto& lo = laser_.options();
    // Zero the laser at the reference point with the compensator cycling: the
    // correction in force at the zero must be the one for that position
    // (LaserInterferometer::Setup's own short moves then keep it).
    const double datum = vm_.description().axes[axis].reference_mm;
    MoveAndWait(axis, std::max(0.0, datum - std::max(lo.overrun_mm, 1.0)), lo.feed_mm_min);
    MoveAndWait(axis, datum, lo.feed_mm_min);
    Step(lo.dwell_s);
    laser_.Setup(vm_, axis, datum);
    const int runs = lo.runs;
    const auto targets = laser_.Targets(vm_, axis);
    measure::Measurement m;
    m.source = fmt::format("{}_{}_{}", vm_.AxisName(axis), state, compensated ? "on" : "off");
    m.has_time = true;
    m.sensor_names = result_.channel_names;
    m.SetMeta("axis", vm_.AxisName(axis));
    m.SetMeta("machine", vm_.description().name);
    m.SetMeta("date", vm_.IsoTime());
    m.SetMeta("state", state);
    m.SetMeta("compensation", compensated ? "on" : "off");
    m.SetMeta("coolant", std::string(CoolantStateName(vm_.coolant())));
    m.SetMeta("instrument", "trueaxis virtual laser interferometer (demo, compensator in the loop)");
    const double t0 = vm_.TimeS();
    // The test's start on day/machine_log.csv's clock, as the campaign's files carry it on theirs:
    // `predict --measurement F --temperature-log day/machine_log.csv` replays the day's history.
    m.SetMeta("campaign_time_s", fmt::format("{:.1f}", t0));
    auto record = [&](int run, Direction dir, double target) {
      MoveAndWait(axis, target, lo.feed_mm_min);
      Step(lo.dwell_s);
      m.points.push_back(laser_.Reading(vm_, run, dir, target, t0));
    };
    sim::RunBidirectionalCycle(targets, runs, lo.overrun_mm,
                               [&](double x) { MoveAndWait(axis, x, lo.feed_mm_min); }, record);
    return m;
  }

  void MeasureState(const std::string& state, const std::vector<std::string>& axes) {
    StopAll();
    for (const auto& name : axes) {
      const std::size_t axis = static_cast<std::size_t>(vm_.description().AxisIndex(name));
      StateResult r;
      r.state = state;
      r.axis = name;
      r.date = vm_.IsoTime();
      r.ambient_c = vm_.AmbientC();
      // Compensated first, then uncompensated: the machine cools a little
      // during the tests, so the uncompensated one sees the smaller thermal
      // error — the comparison is conservative.
      SetCompensation(true);
      r.on = Measure(axis, state, true);
      SetCompensation(false);
      r.off = Measure(axis, state, false);
      SetCompensation(true);
      r.eval_on = analysis::Evaluate(r.on);
      r.eval_off = analysis::Evaluate(r.off);
      const std::string nut = Lower(name) + "_nut";
      const double nut_now = MeanSensor(r.off, nut);
      if (state == "cold") cold_nut_[name] = nut_now;
      r.nut_rise_c = cold_nut_.count(name) ? nut_now - cold_nut_[name] : 0;
      const std::string stem = fmt::format("{}_{}", name, Lower(state));
      std::string file_stem;
      for (char c : stem) file_stem += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
      measure::WriteMeasurementCsv(r.on, (fs::path(result_.out_dir) / "day" / (file_stem + "_on.csv")).string());
      measure::WriteMeasurementCsv(r.off, (fs::path(result_.out_dir) / "day" / (file_stem + "_off.csv")).string());
      Progress(fmt::format("{} {}: A = {:.2f} µm uncompensated → {:.2f} µm compensated ({:.1f}×)", state, name,
                           r.eval_off.axis.A_um, r.eval_on.axis.A_um, r.Factor()));
      result_.states.push_back(std::move(r));
    }
  }

  const DemoOptions& o_;
  DemoResult& result_;
  sim::VirtualMachine vm_;
  sim::LaserInterferometer laser_;
  std::vector<std::string> all_axes_;
  std::unique_ptr<station::Installation> installation_;
  runtime::Compensator* comp_ = nullptr;
  std::string machine_log_;
  std::unique_ptr<DayObserver> observer_;
  std::unique_ptr<runtime::LoopRunner> runner_;
  std::function<void(double)> advance_;
  std::map<std::string, double> cold_nut_;
  std::vector<sim::DayFaultDescription> day_faults_;
  // MODBUS mode
  std::mutex vm_mutex_;
  std::unique_lock<std::mutex> vm_lock_;
  std::unique_ptr<drivers::ModbusMachineServer> server_;
  std::unique_ptr<drivers::ModbusCncLink> cnc_client_;
  std::unique_ptr<drivers::ModbusTemperatureSource> temp_client_;
};

}  // namespace

DemoResult RunDemo(const DemoOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw std::invalid_argument("demo options: " + why);
  const auto wall0 = Clock::now();
  auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  auto progress = [&](const std::string& s) {
    if (o.progress) o.progress(s);
  };
  DemoResult result;
  result.out_dir = o.out_dir;
  result.campaign_dir = (fs::path(o.out_dir) / "campaign").string();
  fs::create_directories(fs::path(o.out_dir) / "day");
  const sim::MachineDescription md = sim::ReadMachineFile(o.machine_file);

  std::vector<std::string> axes = o.axes;
  if (axes.empty()) {
    for (const auto& a : md.axes) {
      axes.push_back(a.name);
      if (o.fast) break;
    }
  }
  for (const auto& a : axes)
    if (md.AxisIndex(a) < 0) throw InputError(o.machine_file, 0, "axes", fmt::format("the machine has no axis '{}'", a));
  result.axes = axes;

  // 1. Calibration campaign.
  sim::CampaignOptions c;
  c.out_dir = result.campaign_dir;
  c.seed = o.seed;
  c.axes = axes;
  c.coolant_rest = o.coolant_rest;
  if (!o.ambient_hours.empty()) c.ambient_hours = o.ambient_hours;
  if (o.ambient_day_offsets) c.ambient_day_offsets = *o.ambient_day_offsets;
  if (o.fast) {
    c.laser.runs = 3;
    c.warm_runs = 2;
    c.max_warm_measurements = 6;
    c.max_coolant_measurements = 3;
  }
  c.min_warmup_per_test = o.min_warmup_per_test;
  if (!o.coolant_prewarm_h.empty()) c.coolant_prewarm_h = o.coolant_prewarm_h;
  c.coolant_visit = o.coolant_visit;
  c.progress = [&](const std::string& line) { progress("[campaign] " + line); };
  progress(fmt::format("[demo] 1/4 calibration campaign on {} (axes {}) → {}", md.name, fmt::join(axes, ","), c.out_dir));
  const auto t_campaign = Clock::now();
  const auto campaign = sim::RunCampaign(md, c);
  result.campaign_wall_s = since(t_campaign);
  progress("[demo] " + campaign.BriefReport());

  // 2. Fit.
  progress("[demo] 2/4 fitting the composite model (per axis and direction)");
  const auto t_fit = Clock::now();
  const auto states = model::LoadFitStates({}, (fs::path(result.campaign_dir) / "manifest.json").string());
  // One fit per axis with the seed's key points, tanβ = k1·ΔT_nut + k2·ΔT_bearing,
  // when the machine has those sensors (the automatic selection otherwise).
  model::FitResult fit;
  for (const auto& axis : axes) {
    std::vector<model::FitState> axis_states;
    for (const auto& st : states)
      if (st.axis == axis) axis_states.push_back(st);
    model::FitOptions fo;
    const std::string nut = Lower(axis) + "_nut", bearing = Lower(axis) + "_bearing";
    const auto& sensors = axis_states.front().measurement.sensor_names;
    if (o.keys == "seed" && std::find(sensors.begin(), sensors.end(), nut) != sensors.end() &&
        std::find(sensors.begin(), sensors.end(), bearing) != sensors.end())
      fo.key_sensors = {nut, bearing};
    if (o.geometric == "table") fo.geometric = model::FitOptions::Geometric::kTable;
    if (!o.thermal_lag) fo.key_lag_grid_s = {0};
    fo.secondary_key_ridge = o.secondary_key_ridge;
    if (!o.lag_fall) fo.key_lag_fall_grid = {1};
    fo.key_offsets = o.key_offsets == "on"    ? model::FitOptions::KeyOffsets::kOn
                     : o.key_offsets == "off" ? model::FitOptions::KeyOffsets::kOff
                                              : model::FitOptions::KeyOffsets::kAuto;
    fo.motion_lag_grid_s = o.motion_lag_grid_s;
    fo.motion_heat = o.motion_heat == "on"    ? model::FitOptions::MotionHeat::kOn
                     : o.motion_heat == "off" ? model::FitOptions::MotionHeat::kOff
                                              : model::FitOptions::MotionHeat::kAuto;
    fo.coolant_soak_constraint = o.coolant_soak;
    if (o.coolant_memory) fo.coolant_loss_grid_s = model::FitOptions::CoolantMemoryGridS();
    fo.fallback_models = o.fallback_models;
    fo.redundant_groups = RedundantProbes(md);
    if (!o.fitted_envelope) fo.tan_beta_margin = -1;
    fo.fit_rho_with_cte = o.rho_fit;
    model::FitResult one = model::FitCompositeModel(axis_states, fo);
    // Er(x): the seed-000 polynomial, unless the seed-002 table (linear
    // interpolation between the measured targets) cross-validates better over
    // both directions — a screw's short-wavelength error is not a polynomial.
    const auto& ds = one.summary.axes.front().directions;
    if (o.geometric == "auto" &&
        ds[0].table_cv_rms_um + ds[1].table_cv_rms_um < ds[0].geometric_cv_rms_um + ds[1].geometric_cv_rms_um) {
      fo.geometric = model::FitOptions::Geometric::kTable;
      one = model::FitCompositeModel(axis_states, fo);
    }
    for (auto& a : one.model.axes) fit.model.axes.push_back(std::move(a));
    for (auto& src : one.model.sources) fit.model.sources.push_back(std::move(src));
    for (auto& a : one.summary.axes) fit.summary.axes.push_back(std::move(a));
    for (auto& w : one.summary.warnings) fit.summary.warnings.push_back(axis + ": " + w);
    fit.model.fit_summary[axis] = one.model.fit_summary;
  }
  fit.model.machine = md.name;
  fit.model.generator = "trueaxis 0.1.0 demo";
  result.model_path = (fs::path(o.out_dir) / "model.json").string();
  model::WriteModelFile(fit.model, result.model_path);
  result.fit_wall_s = since(t_fit);
  result.fit_brief = fit.summary.BriefReport();
  progress("[demo] " + result.fit_brief);
  const std::string model_sha = model::Sha256OfFile(result.model_path);

  // 3. The working day with the compensator in the loop.
  progress("[demo] 3/4 simulated working day with the compensator in its loop");
  const auto t_day = Clock::now();
  result.history_path = (fs::path(o.out_dir) / "history.sqlite").string();
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(result.history_path + suffix, ec);
  {
    sim::LaserOptions laser = c.laser;
    station::HistoryConfig history;
    history.db = result.history_path;
    WorkingDay day(md, o, laser, std::make_shared<const model::CompositeModel>(fit.model), result.model_path, result, history);
    day.Run(axes, model_sha, "demo: fitted from " + result.campaign_dir);
    day.CloseLog();
  }
  result.day_wall_s = since(t_day);

  // 4. Report.
  progress("[demo] 4/4 writing the report");
  result.report_path = (fs::path(o.out_dir) / "report.html").string();
  result.wall_s = since(wall0);
  WriteDemoReport(result, o, fit, md);
  progress("[demo] report: " + result.report_path);
  return result;
}

}  // namespace trueaxis::demo
