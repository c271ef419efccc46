#pragma once
// Compensator: seed 000's 实时补偿模块 + 动态调整模块 for every axis of one
// machine. One call of RunCycle() is one compensation cycle:
//
//   read temperatures ─► per channel: validate (hardware flag, NaN, range,
//   rate) and keep the last good value for a limited time
//   read the CNC (positions, servo directions, coolant, CNC-side enable)
//   per axis: pick the forward/reverse model by servo direction (held while
//   stopped), key temperatures through the model's first-order lag (key_lag_s,
//   model/thermal_lag.hpp; none when τ = 0), Predict() with the ambient
//   adjustment and the coolant's gains,
//   correction = −error (docs/sign-convention.md), or the fallback
//   ─► OutputShaper (bound, rate limit, quantise to δ with hysteresis)
//   ─► write all axes; the shaper state advances only if the write succeeded,
//   so after a failed write the next value starts from what the CNC holds.
//
// Real-time contract: RunCycle allocates nothing, takes no lock, and frees
// nothing (models are retired through ModelExchange). All buffers are sized
// in the constructor. Exactly one thread calls RunCycle; PublishModel,
// SetEnabled, SetAxisEnabled, CollectRetired may be called from any other.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/core/direction.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/thermal_state.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/bound_model.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/runtime/model_exchange.hpp"
#include "trueaxis/runtime/output_shaper.hpp"

namespace trueaxis::runtime {

// Alarm bits of one cycle (CycleStatus::alarms). Raised while the condition holds.
enum Alarm : std::uint32_t {
  kAlarmSensorHeld = 1u << 0,          // a key/ambient sensor is faulty; its last good value is used
  kAlarmSensorFallback = 1u << 1,      // a sensor is lost beyond the hold time; fallback active
  kAlarmTemperatureSource = 1u << 2,   // the temperature source could not be read at all
  kAlarmLinkRead = 1u << 3,            // CNC link read failed (or recovering)
  kAlarmLinkWrite = 1u << 4,           // CNC link write failed
  kAlarmNoModelForAxis = 1u << 5,      // an enabled axis has no model (correction ramps to 0)
  kAlarmCorrectionClamped = 1u << 6,   // the model asks for more than max_correction_um
  kAlarmNoModel = 1u << 7,             // no model published yet
  kAlarmModelExtrapolated = 1u << 8,   // the temperatures lie beyond the model's fitted envelope: its
                                       // thermal slope is held at the envelope (model::Prediction::tan_beta_limited)
};
std::string AlarmNames(std::uint32_t alarms);  // "sensor_held|link_read", "" when none (not for the RT thread)

enum class ChannelHealth : std::uint8_t { kOk, kHeld, kLost };

struct ChannelStatus {
  double value_c = 0;      // the value the model used (last good while held; NaN when lost)
  double raw_c = 0;        // the raw reading of this cycle
  ChannelHealth health = ChannelHealth::kLost;
};

struct AxisStatus {
  double cnc_position_mm = 0;   // as read
  double model_position_mm = 0; // in the model's frame
  Direction direction = Direction::kForward;  // model used (held while stopped)
  bool enabled = false;         // effective enable (switches, CNC flag)
  bool thermal_used = false;
  model::Prediction prediction; // zero when not evaluated
  double desired_um = 0;        // target correction (physical µm) before shaping; NaN = hold
  bool clamped = false;         // desired beyond this axis's bound: the output saturates (alarm raised)
  double output_um = 0;         // shaped correction, physical µm
  double written_um = 0;        // value written to the CNC (CNC units: ×2 on diameter axes)
};

struct CycleStatus {
  std::uint64_t cycle = 0;
  double time_s = 0;
  std::uint32_t alarms = 0;
  bool link_read_ok = false;
  bool write_ok = false;
  bool temperatures_ok = false;
  CoolantState coolant = CoolantState::kOff;
  std::uint64_t model_id = 0;   // 0: none
  std::span<const AxisStatus> axes;
  std::span<const ChannelStatus> channels;
};

class Compensator {
 public:
  // `axes` in the CNC link's axis order; `channel_names` in the source's order.
  // Throws std::invalid_argument on invalid options.
  Compensator(CompensatorOptions options, std::vector<AxisInterface> axes, std::vector<std::string> channel_names);
  // Convenience: axis order and channel names taken from the link and source;
  // `interfaces` matched by axis name (missing axes get defaults).
  static std::unique_ptr<Compensator> ForHardware(const CompensatorOptions& options, const hw::CncLink& link,
                                                  const hw::TemperatureSource& source,
                                                  const std::vector<AxisInterface>& interfaces);

  // ---- any thread except the real-time one ----
  // Binds and publishes; the loop picks it up at its next cycle and ramps to
  // the new correction. Throws InputError (label names the model) on a bad binding.
  void PublishModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label);
  void CollectRetired() { exchange_.CollectRetired(); }
  void SetEnabled(bool on) { enabled_.store(on, std::memory_order_relaxed); }
  void SetAxisEnabled(std::size_t axis, bool on) { axis_enabled_[axis].store(on, std::memory_order_relaxed); }
  bool Enabled() const { return enabled_.load(std::memory_order_relaxed); }

  const CompensatorOptions& options() const { return options_; }
  const std::vector<AxisInterface>& axes() const { return axes_; }
  const std::vector<std::string>& channel_names() const { return channel_names_; }

  // ---- the real-time thread ----
  // One cycle at time `now_s` (monotonic seconds: wall clock or simulated).
  const CycleStatus& RunCycle(hw::CncLink& link, hw::TemperatureSource& source, double now_s);
  const CycleStatus& LastStatus() const { return status_; }

 private:
  void ConditionTemperatures(bool read_ok, double now_s);

  CompensatorOptions options_;
  std::vector<AxisInterface> axes_;
  std::vector<std::string> channel_names_;
  ModelExchange<BoundModel> exchange_;
  std::atomic<std::uint64_t> next_model_id_{1};
  std::atomic<bool> enabled_{true};
  std::unique_ptr<std::atomic<bool>[]> axis_enabled_;

  // RT-thread state and scratch, sized in the constructor.
  std::vector<hw::RawTemperature> raw_;
  std::vector<double> last_good_c_;
  std::vector<double> last_good_time_s_;
  std::vector<std::uint8_t> has_good_;
  std::vector<ChannelStatus> channels_;
  std::vector<hw::AxisState> axis_states_;
  hw::CncState cnc_state_;
  std::vector<Direction> last_direction_;
  std::vector<OutputShaperState> shaper_;
  std::vector<OutputShaperState> proposed_;
  std::vector<double> write_buffer_;
  std::vector<AxisStatus> axis_status_;
  double key_temps_[kMaxKeySensors] = {};
  double key_raw_[kMaxKeySensors] = {};
  // The model's thermal state per axis (model::AxisThermalState, advanced by
  // model::AdvanceThermalState: the lagged / observed key temperatures), the time of its last
  // update and the model it belongs to. Restarted at the current readings when the model changes
  // (a new model may have other keys or τ) and while a key sensor is lost.
  std::vector<model::AxisThermalState> thermal_state_;
  std::vector<double> lag_time_s_;
  std::vector<std::uint64_t> lag_model_id_;
  int good_reads_in_row_ = 0;
  std::uint64_t cycle_ = 0;
  CycleStatus status_;
};

}  // namespace trueaxis::runtime
