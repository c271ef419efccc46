#pragma once
// The end-to-end demonstration (issue 5, README's first command):
//
//  1. calibration campaign on the virtual machine with the virtual laser
//     (sim::RunCampaign: cold, warm-up steps, other days, coolant);
//  2. automatic fit of the composite model (model::FitCompositeModel);
//  3. a simulated working day on a NEW run of the same machine (other run
//     seed, other date, so every state is held out from the fit): cold start,
//     machining duty, ambient drift, coolant on and off — with the
//     compensator in its loop over the machine's CncLink/TemperatureSource,
//     one cycle per period of simulated time; at each state the virtual laser
//     measures every axis with compensation on and off;
//  4. ISO 230-2 evaluation of every measurement and one HTML report.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/demo/alarm_tally.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/modelfit/fit_options.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/sim/campaign.hpp"

namespace trueaxis::demo {

struct DemoOptions {
  std::string machine_file;        // sim machine TOML
  std::string out_dir = "out/demo";
  std::uint64_t seed = 1;
  bool fast = false;               // fewer axes/runs/targets: for tests and quick looks
  std::vector<std::string> axes;   // empty: every axis (fast: the first)
  double period_s = 0.010;         // compensation cycle, simulated time
  runtime::CompensatorOptions compensator;  // defaults: ±100 µm, 1 µm per cycle
  // Each axis's bound on |correction| from its fitted model (model::DeriveCompensationBound,
  // capped by compensator.shaper.max_correction_um as the controller's limit); false: the fixed
  // common bound compensator.shaper.max_correction_um for every axis.
  bool derive_bounds = true;
  double controller_limit_um = 1000;  // the CNC compensation input's limit (physical µm)
  // Er(x): "auto" picks the seed-000 polynomial or the seed-002 table by
  // cross-validation per axis; "polynomial" / "table" force one.
  std::string geometric = "auto";
  // Thermal lag of the key sensors (model/thermal_lag.hpp): τ chosen by the fit's LOSO CV
  // (FitOptions::key_lag_grid_s). false: the static model (no lag), for comparison.
  bool thermal_lag = true;
  // Issue 10's coolant memory (model/thermal_state.hpp, FitOptions::coolant_loss_grid_s): tried by
  // the fit when true (FitOptions::CoolantMemoryGridS()); off by default, as in the fit.
  bool coolant_memory = false;
  // A coolant's own gains keep the off gains' soaked response (FitOptions::coolant_soak_constraint).
  bool coolant_soak = false;
  // Fallback models fitted without each key sensor (FitOptions::fallback_models), used by the
  // compensator when a key sensor is lost (machine file [[day_fault]]). false: the geometric part only.
  bool fallback_models = true;
  // The gains' fitted envelope (FitOptions::tan_beta_margin). false (with the coolant memory off):
  // the model before issue 10's coolant work, the baseline of bench/results/zoo.md.
  bool fitted_envelope = true;
  // ρ fitted from the campaign's room temperatures although the machine's CTE is known
  // (model::FitOptions::fit_rho_with_cte), for comparison with the default physical soak.
  bool rho_fit = false;
  // The campaign's stop under coolant after its coolant warm-up (sim::CampaignOptions::coolant_rest).
  bool coolant_rest = true;
  // Ridge on the gains of the keys after the nut (model::FitOptions::secondary_key_ridge); 0: the
  // seed's plain least squares, for comparison (bench/results/zoo.md).
  double secondary_key_ridge = model::FitOptions{}.secondary_key_ridge;
  // Each key's own pivot (model::FitOptions::key_offsets): "auto", "on" or "off" (the seed's one Px).
  std::string key_offsets = "auto";
  // The motion-heat input (model::FitOptions::motion_heat): "auto", "on" or "off" (the default).
  std::string motion_heat = "auto";
  double min_warmup_per_test = sim::CampaignOptions{}.min_warmup_per_test;  // sim::CampaignOptions::min_warmup_per_test
  // Hours of dry machining before each coolant session (sim::CampaignOptions::coolant_prewarm_h);
  // empty: the campaign's default.
  std::vector<double> coolant_prewarm_h;
  // When the campaign measures its coolant sessions (sim::CampaignOptions::coolant_visit).
  sim::CampaignOptions::CoolantVisit coolant_visit = sim::CampaignOptions{}.coolant_visit;
  std::vector<double> motion_lag_grid_s = model::FitOptions{}.motion_lag_grid_s;  // its τ values tried
  // The key sensors: "seed" = the axis's nut and bearing (seed 000's key points) when it has both;
  // "auto" = chosen from every sensor by the fit's cross-validation, as `trueaxis fit` does.
  std::string keys = "seed";
  // A falling key's longer lag (model::FitOptions::key_lag_fall_grid): true = by the fit's CV;
  // false = one τ both ways, for comparison (bench/results/zoo.md).
  bool lag_fall = true;
  // The hours of the day the campaign's ambient days measure the idle machine at
  // (sim::CampaignOptions::ambient_hours); empty: the campaign's default.
  std::vector<double> ambient_hours;
  // The days after the first on which the campaign measures the idle machine at another room
  // temperature (sim::CampaignOptions::ambient_day_offsets); unset: the campaign's default (two
  // other seasons). A short list (e.g. {1, 2}) calibrates in one season only, as a user whose
  // whole campaign falls in one month; the other day then shows what the model does in another.
  std::optional<std::vector<int>> ambient_day_offsets;
  // The working day over MODBUS TCP on 127.0.0.1: the virtual machine behind
  // a ModbusMachineServer (PMC window + ADAM-6015 modules, docs/protocols.md),
  // the compensator on ModbusCncLink / ModbusTemperatureSource. Each cycle is a
  // few real TCP round trips, so use a longer period (the CLI defaults to 100 ms).
  bool modbus = false;
  int modbus_port = 0;
  // The temperature pipeline (signal::MonitoredTemperatureSource: spike rejection, median and
  // low-pass filter, fault status with the compensator's limits) in front of the compensator, as
  // in `trueaxis run`. false: raw readings (for comparison).
  bool signal_processing = true;             // 0: the first free port from 15020 up
  int day_offset = 30;             // the working day: days after the campaign's first day
  int other_day_offset = 250;      // "another day"
  std::function<void(const std::string&)> progress;  // one line per step (stderr in the CLI)

  bool IsValid(std::string* why) const;
};

// One thermal state of the day, one axis: the same laser test with
// compensation off and on, back to back.
struct StateResult {
  std::string state;               // "cold", "warm", "warm+coolant", "other day"
  std::string axis;
  std::string date;                // simulated date/time at the start
  double nut_rise_c = 0;           // nut sensor vs the day's cold measurement
  double ambient_c = 0;
  measure::Measurement off, on;
  analysis::Evaluation eval_off, eval_on;
  double Factor() const { return eval_on.axis.A_um > 0 ? eval_off.axis.A_um / eval_on.axis.A_um : 0; }
  // The pass marks of a held-out test (docs/concepts.md, "Must line, goal"): must — A_on ≤
  // max(20 % of A_off, 2 × R_on), compensation made the axis better (A_on < A_off) and did not
  // scatter it (R_on ≤ 2 × R_off + 2 µm); goal — A_on ≤ max(10 % of A_off, 1.3 × R_on).
  bool UnderMustLine() const;
  bool AtGoal() const;
};

struct DaySample {                 // the day, one sample per minute of machine time
  double time_h = 0;
  std::vector<double> temp_c;      // parallel to DemoResult::channel_names
  std::vector<double> correction_um;  // parallel to axes
  CoolantState coolant = CoolantState::kOff;
  std::uint32_t alarms = 0;
  bool other_day = false;
};

struct DemoResult {
  std::string out_dir, report_path, model_path, campaign_dir, history_path;
  std::vector<std::string> axes, channel_names;  // measured axes; temperature channels
  std::vector<std::string> machine_axes;         // every axis of the machine (DaySample::correction_um)
  std::vector<StateResult> states;
  std::vector<DaySample> day;
  std::string fit_brief;
  runtime::LoopStats loop_stats;
  // The simulated days the compensator ran (ISO date/time, machine clock) and how long it ran in
  // all (cycles × period): the machine stood switched off in between.
  double day_start_s = 0, day_end_s = 0, other_day_start_s = 0, other_day_end_s = 0;  // Unix s
  std::string DaySpans() const;  // "2026-04-01 07:00–20:31 (13:31 h) and 2026-11-07 10:00–11:38 (1:38 h)"
  double compensated_s = 0;
  double period_s = 0;
  double wall_s = 0, campaign_wall_s = 0, fit_wall_s = 0, day_wall_s = 0;
  std::uint32_t alarms_seen = 0;
  // Per machine axis (parallel to machine_axes): the compensation bound used and how it was
  // found, and how many cycles the model asked for more (the output saturated, alarm raised).
  std::vector<double> bound_um;
  std::vector<std::string> bound_source;
  std::vector<std::uint64_t> clamped_cycles;
  // Per machine axis: cycles in which the model's thermal slope was held at its fitted envelope
  // (model::Prediction::tan_beta_limited, alarm model_extrapolated).
  std::vector<std::uint64_t> extrapolated_cycles;
  // Per machine axis: cycles in which the room temperature lay outside the fit's range (the ρ
  // term extrapolated, not held: model::Prediction::ambient_extrapolated, alarm model_extrapolated).
  std::vector<std::uint64_t> room_extrapolated_cycles;
  // Per machine axis: cycles the sensor fault policy ran it without its thermal part (a key sensor
  // lost: alarm sensor_fallback), and the working day's sensor faults (machine file [[day_fault]]).
  std::vector<std::uint64_t> sensor_fallback_cycles;
  std::vector<std::uint64_t> fallback_model_cycles;  // ... and with the model's fallback (AxisModel::fallbacks)
  std::vector<std::uint64_t> averaged_fallback_cycles;  // ... of those, with fallbacks replacing the lost sensor averaged
  std::vector<std::string> sensor_faults;
  std::uint64_t day_cycles = 0;
  std::string interface_used;      // "in-process CncLink" or "MODBUS TCP 127.0.0.1:<port>"
  std::vector<std::string> alarm_log;  // "<date> <alarms>" at each change (the first 200)
  std::size_t alarm_changes = 0;       // every change, also those beyond the log's 200
  std::vector<AlarmSummaryRow> alarm_summary;  // per alarm: how often, how long, when
  std::string BriefReport() const;  // the before/after table as text
};

DemoResult RunDemo(const DemoOptions& options);

}  // namespace trueaxis::demo
