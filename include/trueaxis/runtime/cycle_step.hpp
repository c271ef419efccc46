#pragma once
// The compensation cycle as a pure function (seed 000's 实时补偿模块 + 动态调整模块):
//
//   Step(model, state, inputs) → (state', outputs)
//
// `model` is what the step computes with (options, per-axis interface, the bound
// model in force); `state` is everything the cycle remembers from one cycle to the
// next (StepState: sensor conditioning, link recovery, held directions, the output
// shaper, and the model-side dynamic state in one sub-struct); `inputs` are the
// latest I/O snapshots with their age and the enable switches. Step does no I/O,
// reads no clock, takes no lock and allocates nothing: the same inputs give the
// same outputs. The I/O phases (io_snapshot.hpp) run around it — inline for an
// in-process plant, on I/O workers with their own rates for real hardware
// (LoopRunner) — so the step never waits on a socket (docs/runtime.md).
//
// A snapshot older than its limit is a fault handled like a failed read: stale
// temperatures → the channels are held, then lost (fallback); a stale CNC
// snapshot → link loss (hold or ramp to zero). Every change of the output goes
// through the one OutputShaper, so it ramps, never jumps.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/direction.hpp"
#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/thermal_state.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/bound_model.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/runtime/io_snapshot.hpp"
#include "trueaxis/runtime/output_shaper.hpp"

namespace trueaxis::runtime {

// Alarm bits of one cycle (CycleStatus::alarms). Raised while the condition holds.
enum Alarm : std::uint32_t {
  kAlarmSensorHeld = 1u << 0,          // a key/ambient sensor is faulty; its last good value is used
  kAlarmSensorFallback = 1u << 1,      // a sensor is lost beyond the hold time; fallback active
  kAlarmTemperatureSource = 1u << 2,   // the temperature source could not be read (failed or stale)
  kAlarmLinkRead = 1u << 3,            // CNC link read failed, stale or recovering
  kAlarmLinkWrite = 1u << 4,           // CNC link write failed
  kAlarmNoModelForAxis = 1u << 5,      // an enabled axis has no model (correction ramps to 0)
  kAlarmCorrectionClamped = 1u << 6,   // the model asks for more than max_correction_um
  kAlarmNoModel = 1u << 7,             // no model published yet
  kAlarmStaleInput = 1u << 8,          // an I/O snapshot is older than its limit (an I/O worker is stuck)
  kAlarmModelExtrapolated = 1u << 9,   // the temperatures lie beyond the model's fitted envelope: its
                                       // thermal slope is held at the envelope (model::Prediction::tan_beta_limited)
  kAlarmVisionStop = 1u << 10,         // the camera's stop rule (seed 001): > 5 non-credible readings in a row;
                                       // the CNC is in feed hold until the marker is redrawn (docs/vision.md)
  kAlarmOutsideMeasuredRange = 1u << 11,  // the axis is beyond the range its geometric part (a pitch table) was
                                          // measured over: the end value is held (model::Prediction::position_outside_range)
};
std::string AlarmNames(std::uint32_t alarms);  // "sensor_held|link_read", "" when none (not for the RT thread)
// The same with the axes behind each alarm an axis raised (AxisStatus::alarms), as a user reads
// it: "no_model_for_axis(Y Z)|link_read". `axis_alarms[i]` are axis i's bits, `axis_names[i]` its
// name (an axis without a name: its index). Not for the RT thread.
std::string AlarmNamesWithAxes(std::uint32_t alarms, std::span<const std::uint32_t> axis_alarms,
                               std::span<const std::string> axis_names);

enum class ChannelHealth : std::uint8_t { kOk, kHeld, kLost };

struct ChannelStatus {
  double value_c = 0;      // the value the model used (last good while held; NaN when lost)
  double raw_c = 0;        // the raw reading of the snapshot in force (NaN when failed or stale)
  ChannelHealth health = ChannelHealth::kLost;
};

struct AxisStatus {
  double cnc_position_mm = 0;   // as read
  double model_position_mm = 0; // in the model's frame
  Direction direction = Direction::kForward;  // model used (held while stopped)
  bool enabled = false;         // effective enable (switches, CNC flag)
  bool thermal_used = false;
  int fallback_model = -1;      // thermal part from the model's fallback #n (a key sensor lost); -1: the model's own
  int fallbacks_averaged = 0;   // with fallback_model: how many fallbacks replacing the same sensor were averaged (≥ 1)
  model::Prediction prediction; // zero when not evaluated
  double extra_error_um = 0;     // StepInputs::extra_error_um used this cycle (error sign; 0 = none)
  double desired_um = 0;        // target correction (physical µm) before shaping; NaN = hold
  bool clamped = false;         // desired beyond this axis's bound: the output saturates (alarm raised)
  double output_um = 0;         // shaped correction, physical µm
  double written_um = 0;        // value written to the CNC (CNC units: ×2 on diameter axes)
  std::uint32_t alarms = 0;     // the Alarm bits this axis raised this cycle (also in CycleStatus::alarms)
};

// How an axis is compensated, in one word (the history's compensation state, the workshop
// server's axis `state`): "link_lost" (the CNC could not be read), "disabled", "geometric" (no
// thermal part: a key sensor lost without a usable fallback), "fallback_model" (a fallback fitted
// without a lost sensor), "full" (the model with its own sensors). Not for the RT thread's output.
const char* AxisCompensationState(bool link_read_ok, bool enabled, bool thermal_used, int fallback_model);

struct CycleStatus {
  std::uint64_t cycle = 0;
  double time_s = 0;
  std::uint32_t alarms = 0;
  bool link_read_ok = false;
  bool write_ok = false;
  bool temperatures_ok = false;
  double temperature_age_s = 0;  // age of the temperature snapshot in force
  double cnc_age_s = 0;          // age of the CNC snapshot in force
  CoolantState coolant = CoolantState::kOff;
  std::uint64_t model_id = 0;   // 0: none
  std::span<const AxisStatus> axes;
  std::span<const ChannelStatus> channels;
};

// ---- state ----

// Conditioning memory of one temperature channel.
struct ChannelMemory {
  double last_good_c = 0;
  double last_good_time_s = 0;  // sample time of the last good value
  bool has_good = false;
  bool valid = false;           // the latest sample conditioned was good
};

// ALL model-side dynamic state of the cycle (today: the first-order lag of the key
// temperatures, model::LagStep with AxisModel::key_lag_s), advanced once per cycle
// by AdvanceModelDynamics — the one place to add further per-axis dynamics
// (per-sensor lags, a screw-temperature observer, ...).
struct ModelDynamics {
  struct Axis {
    // The model's thermal state (model::AdvanceThermalState: key temperatures lagged and, under a
    // coolant, drawn to the room — issue 10's coolant memory).
    model::AxisThermalState thermal;
    std::uint64_t fallback_model_id = 0;  // model the fallback states belong to (0: restart them)
    double time_s = 0;                            // time of the last update
    std::uint64_t model_id = 0;  // model the state belongs to; 0 = restart at the readings
    // The model's own sensors (keys and ambient) all read in the last cycle, and the room reading
    // then (NaN: none): what the hand-over to a fallback starts from.
    bool own_sensors_read = false;
    double ambient_c = std::numeric_limits<double>::quiet_NaN();
  };
  std::vector<Axis> axes;
  // Per axis, the state of a model behind model::AxisErrorModel that has dynamics (its lagged
  // inputs and the interval trend: ≈ 7.8 kB an axis). Sized with the axes by a StepState that may
  // step such models; empty for one that steps composite models only (StepState's
  // `generic_models`), which then holds none of it.
  std::vector<model::AxisModelDynamics> generic;
  // Per axis, the same state for each of its fallback models (BoundAxis::fallbacks), advanced
  // alongside so a fallback taking over has the machine's history, not a cold start. Kept apart
  // from `axes`: a cycle without fallbacks does not pull them through the cache.
  std::vector<std::array<model::AxisThermalState, kMaxFallbackModels>> fallback_thermal;
  // Per axis and fallback, the hand-over taken in the cycle the model lost its own sensors: the
  // model's thermal + ambient error then, minus the fallback's, as a line in the model position per
  // direction (at0_um + per_mm · P0). The fallback taking over adds it, decaying with
  // SensorFaultPolicy::fallback_handover_s while the coolant state stays as it was, so the
  // correction does not jump away from the model that was the better one a moment ago.
  // start_s NaN: none (the model's sensors read again, or the fallback had no state at the loss).
  struct Handover {
    double start_s = std::numeric_limits<double>::quiet_NaN();
    // The coolant state at the loss: the difference was taken with that state's gains, so it
    // says nothing once another coolant state's gains are in use, and is then no longer carried.
    CoolantState coolant = CoolantState::kOff;
    std::array<double, 2> at0_um{};  // [forward, reverse]
    std::array<double, 2> per_mm{};
  };
  std::vector<std::array<Handover, kMaxFallbackModels>> fallback_handover;
};

struct StepState {
  std::uint64_t cycle = 0;
  std::vector<ChannelMemory> channels;
  std::uint64_t temperature_sequence = 0;  // last temperature snapshot conditioned
  std::uint64_t cnc_sequence = 0;          // last CNC snapshot seen
  int good_reads_in_row = 0;
  hw::CncState machine;                    // from the last good CNC read
  std::vector<Direction> direction;        // per axis, held while stopped
  // Per axis, what the direction rule (docs/runtime.md step 4) compares the next CNC snapshot
  // with: the output the CNC held at the last good read, and the turning point — the farthest
  // model position reached in the held direction since the model last switched (NaN: none yet),
  // with the output the CNC held at that read and at the read before it (a CNC may show the
  // compensation in its position a cycle late).
  struct LastRead {
    double held_um = 0;
    double turn_position_mm = std::numeric_limits<double>::quiet_NaN();
    double turn_held_um = 0;
    double turn_held_before_um = 0;
  };
  std::vector<LastRead> last_read;
  std::vector<OutputShaperState> shaper;   // per axis: what the CNC holds
  // Asynchronous writes: at most one command is outstanding. Its proposal waits here until a
  // snapshot reports it written (the shaper advances to it) or failed; until then the step hands
  // out the same command again, so every value written is one step from what the CNC holds.
  std::vector<OutputShaperState> pending;
  std::uint64_t outstanding = 0;           // sequence of the outstanding command; 0 = none
  ModelDynamics dynamics;
  std::vector<double> model_position_mm;   // per axis, this cycle's (NaN: not known): the motion-heat input

  StepState() = default;
  // `generic_models`: the state may step models behind model::AxisErrorModel (ModelDynamics::generic
  // sized); false: composite models only.
  StepState(std::size_t axis_count, std::size_t channel_count, const CompensatorOptions& options,
            bool generic_models = true);
};

// ---- inputs and outputs ----

struct StepInputs {
  double now_s = 0;                               // loop time of this cycle
  const TemperatureSnapshot* temperatures = nullptr;
  const CncSnapshot* cnc = nullptr;
  bool enabled = true;                            // global switch
  std::span<const std::uint8_t> axis_enabled;     // per axis switch (empty: all on)
  // An additional error per axis measured outside the model (µm, error sign, docs/sign-convention.md),
  // e.g. the spindle's Δz from the camera (seed 001) on Z. Added to the model's predicted error of an
  // enabled axis before the output shaper (so the correction gets its negative, bounded, rate-limited
  // and quantised like the rest). Empty = none; NaN for an axis = none. The supplier owns its
  // freshness: the Compensator drops a term past its validity (alarm stale_input), docs/runtime.md.
  std::span<const double> extra_error_um;
};

// What the step computes with: fixed per installation, plus the model in force (may be null).
struct StepModel {
  const CompensatorOptions& options;
  std::span<const AxisInterface> axes;
  const BoundModel* bound = nullptr;
  // Per axis: the shaper's constants (options with the axis's own bound, its physical quantum),
  // computed once by the Compensator (ShaperLimitsFor). Empty: computed every cycle.
  std::span<const ShaperLimits> shaping = {};
};

// The shaping constants of every axis of an installation (what StepModel::shaping holds).
std::vector<ShaperLimits> ShaperLimitsFor(const CompensatorOptions& options, std::span<const AxisInterface> axes);

// Sized once; `status` points into `axes` / `channels`.
struct StepOutputs {
  std::vector<AxisStatus> axes;
  std::vector<ChannelStatus> channels;
  std::vector<OutputShaperState> proposed;  // the shaper state if the command is written
  CncCommand command;                       // to write (CNC units)
  CycleStatus status;

  StepOutputs(std::size_t axis_count, std::size_t channel_count);
  StepOutputs(const StepOutputs&) = delete;
  StepOutputs& operator=(const StepOutputs&) = delete;
};

// The cycle. Writes `out` (the command to write; the status with the output the CNC holds) and
// advances `state`, except the shaper: it advances only once the CNC has accepted a value, so a
// ramp always continues from what the CNC holds and a failed or late write never makes it jump.
void Step(const StepModel& model, StepState& state, const StepInputs& inputs, StepOutputs& out);
// Inline write phase done: the shaper advances to the proposal if the write succeeded.
void CommitWrite(const StepModel& model, StepState& state, bool write_ok, StepOutputs& out);
// Asynchronous write phase: the command goes to the CNC worker; its proposal is kept until a
// later snapshot acknowledges it (Step then advances the shaper to it) or reports it failed.
void AwaitWrite(const StepModel& model, StepState& state, StepOutputs& out);
// The model-side dynamics (ModelDynamics) for one cycle; called by Step, once.
// `position_mm`: each axis's position in its model's frame this cycle (NaN: not known, e.g. the
// link down), for a model's motion-heat input; empty: none known.
void AdvanceModelDynamics(const BoundModel& bound, std::span<const ChannelStatus> channels, CoolantState coolant,
                          double now_s, ModelDynamics& dynamics, std::span<const double> position_mm = {});

}  // namespace trueaxis::runtime
