#include "trueaxis/runtime/cycle_step.hpp"

#include <algorithm>
#include <cmath>
#include <new>

#include "trueaxis/model/thermal_state.hpp"

namespace trueaxis::runtime {

static_assert(kMaxKeySensors <= model::kMaxStateKeys, "the model's thermal state must hold every key sensor");

std::string AlarmNames(std::uint32_t alarms) {
  static const char* const kNames[] = {"sensor_held", "sensor_fallback",   "temperature_source",
                                       "link_read",   "link_write",        "no_model_for_axis",
                                       "correction_clamped", "no_model", "stale_input", "model_extrapolated",
                                       "vision_stop", "outside_measured_range"};
  std::string out;
  for (std::size_t i = 0; i < std::size(kNames); ++i) {
    if (alarms & (1u << i)) {
      if (!out.empty()) out += '|';
      out += kNames[i];
    }
  }
  return out;
}

std::string AlarmNamesWithAxes(std::uint32_t alarms, std::span<const std::uint32_t> axis_alarms,
                               std::span<const std::string> axis_names) {
  std::string out;
  for (std::uint32_t bit = 1; bit != 0 && bit <= alarms; bit <<= 1) {
    if (!(alarms & bit)) continue;
    if (!out.empty()) out += '|';
    out += AlarmNames(bit);
    std::string axes;
    for (std::size_t i = 0; i < axis_alarms.size(); ++i)
      if (axis_alarms[i] & bit) {
        if (!axes.empty()) axes += ' ';
        axes += i < axis_names.size() && !axis_names[i].empty() ? axis_names[i] : std::to_string(i);
      }
    if (!axes.empty()) out += "(" + axes + ")";
  }
  return out;
}

const char* AxisCompensationState(bool link_read_ok, bool enabled, bool thermal_used, int fallback_model) {
  return !link_read_ok        ? "link_lost"
         : !enabled           ? "disabled"
         : !thermal_used      ? "geometric"
         : fallback_model >= 0 ? "fallback_model"
                              : "full";
}

StepState::StepState(std::size_t axis_count, std::size_t channel_count, const CompensatorOptions& options,
                     bool generic_models)
    : channels(channel_count),
      good_reads_in_row(options.link_recovery_cycles),  // start as if connected; the first read decides
      direction(axis_count, Direction::kForward),
      last_read(axis_count),
      shaper(axis_count),
      pending(axis_count),
      model_position_mm(axis_count, std::nan("")) {
  dynamics.axes.resize(axis_count);
  dynamics.fallback_thermal.resize(axis_count);
  dynamics.fallback_handover.resize(axis_count);
  if (generic_models) dynamics.generic.resize(axis_count);
}

StepOutputs::StepOutputs(std::size_t axis_count, std::size_t channel_count)
    : axes(axis_count), channels(channel_count), proposed(axis_count), command(axis_count) {
  status.axes = axes;
  status.channels = channels;
}

namespace {

// Temperature conditioning. Every value was judged once, before the step, by the temperature
// judge (signal::TemperatureMonitor: calibration, range, rate, stuck, disagreement); the step adds
// only what concerns the snapshot and the time: a channel is good when the snapshot is fresh and
// answered and the judge found the channel usable. A channel that is not keeps its last good value
// for hold_last_good_s, then is lost. Returns whether the temperature snapshot was usable.
bool ConditionTemperatures(const SensorFaultPolicy& p, const TemperatureSnapshot* ts, double now_s,
                           StepState& state, StepOutputs& out, std::uint32_t& alarms) {
  const bool have = ts && ts->sequence != 0;
  const bool stale = have && now_s - ts->sampled_at_s > p.stale_after_s;
  const bool usable = have && ts->ok && !stale;
  const bool new_sample = usable && ts->sequence != state.temperature_sequence;
  if (!usable) alarms |= kAlarmTemperatureSource;
  if (stale) alarms |= kAlarmStaleInput;
  if (usable) state.temperature_sequence = ts->sequence;
  for (std::size_t i = 0; i < state.channels.size(); ++i) {
    ChannelMemory& m = state.channels[i];
    ChannelStatus& c = out.channels[i];
    if (!usable) {
      m.valid = false;
    } else if (new_sample) {
      const signal::JudgedTemperature& j = ts->channels[i];
      const bool valid = j.usable() && std::isfinite(j.value_c);
      if (valid) {
        m.last_good_c = j.value_c;
        m.last_good_time_s = ts->sampled_at_s;
        m.has_good = true;
      }
      m.valid = valid;
    }
    c.raw_c = usable ? ts->channels[i].raw_c : std::nan("");
    if (m.valid) {
      c.value_c = m.last_good_c;
      c.health = ChannelHealth::kOk;
    } else if (m.has_good && now_s - m.last_good_time_s <= p.hold_last_good_s) {
      c.value_c = m.last_good_c;
      c.health = ChannelHealth::kHeld;
    } else {
      c.value_c = std::nan("");
      c.health = ChannelHealth::kLost;
    }
  }
  return usable;
}

// The CNC snapshot: new reads count towards link recovery; a stale snapshot is a link loss; an
// acknowledged asynchronous write advances the shaper to what the CNC now holds. Returns "link usable".
bool TakeCncSnapshot(const StepModel& model, const CncSnapshot* cs, double now_s, StepState& state,
                     bool& read_ok, std::uint32_t& alarms) {
  const CompensatorOptions& o = model.options;
  const bool have = cs && cs->sequence != 0;
  const bool stale = have && now_s - cs->sampled_at_s > o.link_stale_after_s;
  if (stale) alarms |= kAlarmStaleInput;
  if (have && cs->sequence != state.cnc_sequence) {
    state.cnc_sequence = cs->sequence;
    state.good_reads_in_row = cs->read_ok ? state.good_reads_in_row + 1 : 0;
    if (cs->read_ok) state.machine = cs->machine;
  }
  if (have && state.outstanding != 0) {
    if (cs->written_sequence == state.outstanding) {
      for (std::size_t i = 0; i < model.axes.size(); ++i) state.shaper[i] = state.pending[i];
      state.outstanding = 0;
    } else if (cs->attempted_sequence == state.outstanding && cs->write_failed) {
      state.outstanding = 0;  // the CNC still holds the shaper's value
    }
  }
  if (have && cs->write_failed) alarms |= kAlarmLinkWrite;
  if (!have || stale) state.good_reads_in_row = 0;
  read_ok = have && !stale && cs->read_ok;
  const bool usable = read_ok && state.good_reads_in_row >= o.link_recovery_cycles;
  if (!usable) alarms |= kAlarmLinkRead;
  return usable;
}

// What a model behind model::AxisErrorModel sees of its dynamics in a state sized without them
// (ModelDynamics::generic empty): a model that has none ignores them; one that has them is refused
// by a Compensator for composite models only before it could be stepped.
const model::AxisModelDynamics kNoGenericDynamics{};

// An axis bound to a model behind model::AxisErrorModel: its sensors' conditioned values; a lost
// sensor ramps the axis to zero (there is no geometric-only part to fall back to).
double GenericCorrection(const BoundAxis& ba, std::size_t i, const StepState& state, const StepOutputs& out,
                         AxisStatus& st, std::uint32_t& alarms) {
  double sensors[kMaxKeySensors];
  for (std::size_t k = 0; k < ba.generic_channel.size(); ++k) {
    const ChannelStatus& c = out.channels[static_cast<std::size_t>(ba.generic_channel[k])];
    if (c.health == ChannelHealth::kHeld) alarms |= kAlarmSensorHeld;
    if (c.health == ChannelHealth::kLost) {
      alarms |= kAlarmSensorFallback;
      return 0;
    }
    sensors[k] = c.value_c;
  }
  const double error = ba.generic->ErrorUm(st.model_position_mm, st.direction,
                                           std::span<const double>(sensors, ba.generic_channel.size()), state.machine.coolant,
                                           i < state.dynamics.generic.size() ? state.dynamics.generic[i] : kNoGenericDynamics);
  st.prediction.thermal_um = error;
  st.prediction.total_um = error;
  st.thermal_used = true;
  return std::isfinite(error) ? -error : 0.0;  // a broken model never drives the axis
}

// Whether every key channel of `b` is usable (ok or held; a held one raises sensor_held).
bool KeysRead(const BoundAxis& b, std::span<const ChannelStatus> channels, std::uint32_t& alarms) {
  bool ok = true;
  for (int ch : b.key_channel) {
    const ChannelStatus& c = channels[static_cast<std::size_t>(ch)];
    if (c.health == ChannelHealth::kHeld) alarms |= kAlarmSensorHeld;
    if (c.health == ChannelHealth::kLost) ok = false;
  }
  return ok;
}

// The desired correction of one axis (physical µm; NaN = hold).
double DesiredCorrection(const StepModel& model, const StepState& state, const StepInputs& in, std::size_t i,
                         bool link_usable, StepOutputs& out, std::uint32_t& alarms) {
  const CompensatorOptions& o = model.options;
  const AxisInterface& ai = model.axes[i];
  AxisStatus& st = out.axes[i];
  if (!link_usable) {
    st.enabled = false;
    return o.link_loss == LinkLossPolicy::kHold ? std::nan("") : 0.0;
  }
  const hw::AxisState& as = in.cnc->axes[i];
  st.cnc_position_mm = as.position_mm;
  st.model_position_mm = ai.ModelPositionMm(as.position_mm);
  st.direction = state.direction[i];
  const bool cnc_on = !o.follow_cnc_enable || state.machine.compensation_enabled;
  const bool axis_on = in.axis_enabled.empty() || in.axis_enabled[i] != 0;
  st.enabled = in.enabled && cnc_on && axis_on;
  const BoundAxis* ba = model.bound ? &model.bound->axes[i] : nullptr;
  if (st.enabled && ba && !ba->has_model) alarms |= kAlarmNoModelForAxis;
  if (!st.enabled || !ba || !ba->has_model) return 0;
  if (ba->generic) return GenericCorrection(*ba, i, state, out, st, alarms);

  // The model's own keys; when one of them or its ambient sensor is lost, the first fallback model
  // whose sensors all read (its state advanced alongside), else the sensor fault policy (a lost
  // ambient alone: the model without its room term).
  const ModelDynamics::Axis& dyn = state.dynamics.axes[i];
  const BoundAxis* use = ba;
  const model::AxisThermalState* thermal = &dyn.thermal;
  const auto ambient_lost = [&](const BoundAxis& b) {
    return b.ambient_channel >= 0 && out.channels[static_cast<std::size_t>(b.ambient_channel)].health == ChannelHealth::kLost;
  };
  bool keys_ok = KeysRead(*ba, out.channels, alarms);
  bool fallback_without_room = false;  // the fallback runs without its room term (a key and the room lost)
  if (!keys_ok || ambient_lost(*ba)) {
    alarms |= kAlarmSensorFallback;
    const std::size_t n_fallbacks = i < state.dynamics.fallback_thermal.size() ? ba->fallbacks.size() : 0;
    // First a fallback whose keys and room sensor all read; failing that (a key and the room sensor
    // both lost, while the model's keys do not read), one whose keys read, without its room term —
    // as the model itself goes on when only its room sensor is lost.
    for (int pass = 0; pass < 2 && use == ba && !(pass == 1 && keys_ok); ++pass) {
      for (std::size_t f = 0; f < n_fallbacks; ++f) {
        std::uint32_t unused = 0;
        const model::AxisThermalState& ft = state.dynamics.fallback_thermal[i][f];
        const bool room_ok = pass == 1 || !ambient_lost(ba->fallbacks[f]);
        if (ft.valid && KeysRead(ba->fallbacks[f], out.channels, unused) && room_ok) {
          use = &ba->fallbacks[f];
          thermal = &ft;
          st.fallback_model = static_cast<int>(f);
          fallback_without_room = pass == 1;
          keys_ok = true;
          break;
        }
      }
    }
  }
  double key_temps[kMaxKeySensors];
  for (std::size_t k = 0; k < use->key_channel.size(); ++k)
    key_temps[k] = thermal->key_c[k];  // = the readings when the model has no lag or loss
  double ambient = std::nan("");
  if (use->ambient_channel >= 0) {
    const ChannelStatus& c = out.channels[static_cast<std::size_t>(use->ambient_channel)];
    if (c.health == ChannelHealth::kHeld) alarms |= kAlarmSensorHeld;
    if (c.health == ChannelHealth::kLost) alarms |= kAlarmSensorFallback;  // ambient adjustment dropped
    ambient = c.value_c;
  }
  if (!keys_ok && o.sensor.fallback == SensorFallback::kZero) return 0;
  model::ThermalState ts{std::span<const double>(key_temps, use->key_channel.size()), ambient,
                         state.machine.coolant, keys_ok, thermal->motion_m_per_min};
  // Constructed in place (guaranteed elision: Predict writes st.prediction itself). Assigning would
  // go through a temporary whose wide copy then stalls on store forwarding: ~5 ns per axis.
  ::new (&st.prediction) model::Prediction(model::Predict(use->model, st.model_position_mm, st.direction, ts));
  // The hand-over (ModelDynamics::Handover): from the model's last correction to fallback f's.
  const auto handover_um = [&](std::size_t f) {
    if (o.sensor.fallback_handover_s <= 0 || i >= state.dynamics.fallback_handover.size()) return 0.0;
    const ModelDynamics::Handover& h = state.dynamics.fallback_handover[i][f];
    if (!std::isfinite(h.start_s) || h.coolant != state.machine.coolant) return 0.0;
    const int d = st.direction == Direction::kReverse ? 1 : 0;
    return (h.at0_um[d] + h.per_mm[d] * st.model_position_mm) *
           std::exp(-std::max(0.0, in.now_s - h.start_s) / o.sensor.fallback_handover_s);
  };
  if (st.fallback_model >= 0) {
    const auto first = static_cast<std::size_t>(st.fallback_model);
    const double carried_um = handover_um(first);
    st.prediction.thermal_um += carried_um;
    st.prediction.total_um += carried_um;
    st.fallbacks_averaged = 1;
    // The other fallbacks fitted without the same sensor that can run now are averaged with it: the
    // campaign's CV does not rank them the way a working day does (AxisModel::replaces).
    const std::string& replaced = use->model.replaces;
    double sum_um = st.prediction.total_um - st.prediction.geometric_um;
    double sum_thermal_um = st.prediction.thermal_um, sum_ambient_um = st.prediction.ambient_um;
    double sum_tan_beta = st.prediction.tan_beta_um_per_mm;
    for (std::size_t f = first + 1; f < ba->fallbacks.size() && !replaced.empty(); ++f) {
      const BoundAxis& other = ba->fallbacks[f];
      const model::AxisThermalState& ft = state.dynamics.fallback_thermal[i][f];
      std::uint32_t unused = 0;
      if (other.model.replaces != replaced || !ft.valid || !KeysRead(other, out.channels, unused)) continue;
      const bool room_read = !ambient_lost(other);
      if (!room_read && !fallback_without_room) continue;  // the first pass: its room sensor must read
      double other_temps[kMaxKeySensors];
      for (std::size_t k = 0; k < other.key_channel.size(); ++k) other_temps[k] = ft.key_c[k];
      const double other_ambient = other.ambient_channel >= 0 && room_read
                                       ? out.channels[static_cast<std::size_t>(other.ambient_channel)].value_c
                                       : std::nan("");
      const model::ThermalState ots{std::span<const double>(other_temps, other.key_channel.size()), other_ambient,
                                    state.machine.coolant, true, ft.motion_m_per_min};
      const model::Prediction p = model::Predict(other.model, st.model_position_mm, st.direction, ots);
      const double carried = handover_um(f);
      sum_um += p.total_um - p.geometric_um + carried;
      sum_thermal_um += p.thermal_um + carried;
      sum_ambient_um += p.ambient_um;
      sum_tan_beta += p.tan_beta_um_per_mm;
      st.prediction.tan_beta_limited = st.prediction.tan_beta_limited || p.tan_beta_limited;
      st.prediction.ambient_extrapolated = st.prediction.ambient_extrapolated || p.ambient_extrapolated;
      ++st.fallbacks_averaged;
    }
    if (st.fallbacks_averaged > 1) {
      const double n = st.fallbacks_averaged;
      st.prediction.thermal_um = sum_thermal_um / n;
      st.prediction.ambient_um = sum_ambient_um / n;
      st.prediction.total_um = st.prediction.geometric_um + sum_um / n;
      st.prediction.tan_beta_um_per_mm = sum_tan_beta / n;
    }
  }
  st.thermal_used = keys_ok;
  // Held at the fitted envelope, or the room outside the fitted range (extrapolated): both alarmed.
  if (st.prediction.tan_beta_limited || st.prediction.ambient_extrapolated) alarms |= kAlarmModelExtrapolated;
  if (st.prediction.position_outside_range) alarms |= kAlarmOutsideMeasuredRange;
  const double desired = model::CorrectionUm(st.prediction);
  return std::isfinite(desired) ? desired : 0.0;  // a broken model never drives the axis
}

}  // namespace

namespace {
// A model behind the generic interface with dynamics: advanced with its sensors while all are
// usable; a lost sensor or a new model restarts it (the model then predicts as at start-up).
void AdvanceGenericDynamics(const BoundAxis& ba, std::span<const ChannelStatus> channels, double now_s,
                            std::uint64_t model_id, ModelDynamics::Axis& d, model::AxisModelDynamics& generic) {
  double sensors[kMaxKeySensors];
  bool lost = false;
  const std::size_t n = ba.generic_channel.size();
  for (std::size_t k = 0; k < n; ++k) {
    const ChannelStatus& c = channels[static_cast<std::size_t>(ba.generic_channel[k])];
    lost = lost || c.health == ChannelHealth::kLost;
    sensors[k] = c.value_c;
  }
  if (lost || d.model_id != model_id) ba.generic->ResetDynamics(generic);
  if (!lost) ba.generic->Advance(generic, now_s, std::span<const double>(sensors, n));
  d.time_s = now_s;
  d.model_id = lost ? 0 : model_id;
}
}  // namespace

namespace {
// One keyed model's thermal state (the axis's own or a fallback's) to the channels' values; true
// when one of its keys is lost (the state then restarts at the readings once they all read).
bool AdvanceKeyedState(const BoundAxis& ba, std::span<const ChannelStatus> channels, CoolantState coolant, double dt_s,
                       bool restart, double position_mm, model::AxisThermalState& thermal) {
  const std::size_t n = ba.key_channel.size();
  bool any_lost = false;
  if (!ba.thermal_dynamics) {
    // No lag and no loss: AdvanceThermalState would return the readings (valid when all read).
    // Taken here without the call, the sink or the loss look-up: the common real-time case.
    bool all_read = true;
    for (std::size_t k = 0; k < n; ++k) {
      const ChannelStatus& c = channels[static_cast<std::size_t>(ba.key_channel[k])];
      any_lost = any_lost || c.health == ChannelHealth::kLost;
      all_read = all_read && !std::isnan(c.value_c);
      thermal.key_c[k] = c.value_c;
    }
    thermal.valid = all_read;
    return any_lost;
  }
  double readings[kMaxKeySensors];
  for (std::size_t k = 0; k < n; ++k) {
    const ChannelStatus& c = channels[static_cast<std::size_t>(ba.key_channel[k])];
    any_lost = any_lost || c.health == ChannelHealth::kLost;
    readings[k] = c.value_c;
  }
  if (any_lost || restart) thermal.valid = false;  // restart at the readings
  const double ambient =
      ba.ambient_channel >= 0 ? channels[static_cast<std::size_t>(ba.ambient_channel)].value_c : std::nan("");
  model::AdvanceThermalState(ba.model, thermal, {std::span<const double>(readings, n), ambient, coolant, position_mm},
                             dt_s);
  return any_lost;
}
}  // namespace

namespace {
// The thermal + ambient part of `b`'s error as a line in the model position, per direction:
// at0_um + per_mm · P0 (the model and its fallbacks share Er(x), which cancels in their difference).
void ThermalLine(const BoundAxis& b, const model::AxisThermalState& thermal, double ambient_c, CoolantState coolant,
                 std::array<double, 2>& at0_um, std::array<double, 2>& per_mm) {
  const model::ThermalState ts{std::span<const double>(thermal.key_c.data(), b.key_channel.size()),
                               b.ambient_channel >= 0 ? ambient_c : std::nan(""), coolant, true,
                               thermal.motion_m_per_min};
  constexpr double kSpanMm = 1000;  // any two positions: the part is a line in P0
  for (int d = 0; d < 2; ++d) {
    const Direction dir = d == 0 ? Direction::kForward : Direction::kReverse;
    const model::Prediction p0 = model::Predict(b.model, 0, dir, ts);
    const model::Prediction p1 = model::Predict(b.model, kSpanMm, dir, ts);
    at0_um[d] = p0.thermal_um + p0.ambient_um;
    per_mm[d] = (p1.thermal_um + p1.ambient_um - at0_um[d]) / kSpanMm;
  }
}

bool OwnSensorsRead(const BoundAxis& ba, std::span<const ChannelStatus> channels) {
  for (const int ch : ba.key_channel)
    if (channels[static_cast<std::size_t>(ch)].health == ChannelHealth::kLost) return false;
  return ba.ambient_channel < 0 || channels[static_cast<std::size_t>(ba.ambient_channel)].health != ChannelHealth::kLost;
}

// Called before the states advance, so `d.thermal` and the fallbacks' states are still those of the
// last cycle: in the cycle the model loses one of its own sensors, each fallback with a state gets
// the model's thermal line then minus its own; while the model's sensors all read, none is kept.
void TrackHandover(const BoundAxis& ba, std::span<const ChannelStatus> channels, CoolantState coolant, double now_s,
                   bool restart, ModelDynamics::Axis& d,
                   const std::array<model::AxisThermalState, kMaxFallbackModels>& fallback_thermal,
                   std::array<ModelDynamics::Handover, kMaxFallbackModels>& handover) {
  const bool read = OwnSensorsRead(ba, channels);
  if (read || restart) {
    for (auto& h : handover) h.start_s = std::nan("");
  } else if (d.own_sensors_read && d.thermal.valid) {
    std::array<double, 2> model_at0{}, model_per_mm{};
    ThermalLine(ba, d.thermal, d.ambient_c, coolant, model_at0, model_per_mm);
    for (std::size_t f = 0; f < ba.fallbacks.size(); ++f) {
      ModelDynamics::Handover& h = handover[f];
      h.start_s = std::nan("");
      if (!fallback_thermal[f].valid) continue;
      std::array<double, 2> at0{}, per_mm{};
      ThermalLine(ba.fallbacks[f], fallback_thermal[f], d.ambient_c, coolant, at0, per_mm);
      bool finite = true;
      for (int k = 0; k < 2; ++k) {
        h.at0_um[k] = model_at0[k] - at0[k];
        h.per_mm[k] = model_per_mm[k] - per_mm[k];
        finite = finite && std::isfinite(h.at0_um[k]) && std::isfinite(h.per_mm[k]);
      }
      if (finite) h.start_s = now_s;
      h.coolant = coolant;
    }
  }
  d.own_sensors_read = read && !restart;
  if (ba.ambient_channel >= 0 && read) d.ambient_c = channels[static_cast<std::size_t>(ba.ambient_channel)].value_c;
}
}  // namespace

void AdvanceModelDynamics(const BoundModel& bound, std::span<const ChannelStatus> channels, CoolantState coolant,
                          double now_s, ModelDynamics& dynamics, std::span<const double> position_mm) {
  // Advanced every cycle for every axis with a model, enabled or not, so the lagged temperature
  // tracks the machine's history and not only the time compensation was on. Restarted at the
  // current readings when the model changes (other keys or τ) and once a lost key returns.
  for (std::size_t i = 0; i < bound.axes.size(); ++i) {
    const BoundAxis& ba = bound.axes[i];
    if (!ba.has_model) continue;
    ModelDynamics::Axis& d = dynamics.axes[i];
    if (ba.generic) {
      if (ba.generic_dynamics && i < dynamics.generic.size())
        AdvanceGenericDynamics(ba, channels, now_s, bound.id, d, dynamics.generic[i]);
      continue;
    }
    const double dt_s = now_s - d.time_s;
    const bool fallbacks_restart = d.fallback_model_id != bound.id;
    // (fallback_thermal is sized with the axes by StepState; a hand-made ModelDynamics without it
    // simply has no fallback states, and DesiredCorrection then uses none.)
    const std::size_t n_fallbacks = i < dynamics.fallback_thermal.size() ? ba.fallbacks.size() : 0;
    if (n_fallbacks > 0 && i < dynamics.fallback_handover.size())
      TrackHandover(ba, channels, coolant, now_s, fallbacks_restart, d, dynamics.fallback_thermal[i],
                    dynamics.fallback_handover[i]);
    const double position = i < position_mm.size() ? position_mm[i] : std::nan("");
    const bool any_lost = AdvanceKeyedState(ba, channels, coolant, dt_s, d.model_id != bound.id, position, d.thermal);
    for (std::size_t f = 0; f < n_fallbacks; ++f)
      AdvanceKeyedState(ba.fallbacks[f], channels, coolant, dt_s, fallbacks_restart, position,
                        dynamics.fallback_thermal[i][f]);
    d.fallback_model_id = bound.id;
    d.time_s = now_s;
    d.model_id = any_lost ? 0 : bound.id;
  }
}

namespace {
ShaperLimits AxisShaperLimits(const CompensatorOptions& o, const AxisInterface& ai) {
  OutputShaperOptions so = o.shaper;
  if (!std::isnan(ai.max_correction_um)) so.max_correction_um = ai.max_correction_um;
  return ShaperLimits::For(so, ai.PhysicalQuantumUm());
}
}  // namespace

std::vector<ShaperLimits> ShaperLimitsFor(const CompensatorOptions& options, std::span<const AxisInterface> axes) {
  std::vector<ShaperLimits> out;
  for (const auto& a : axes) out.push_back(AxisShaperLimits(options, a));
  return out;
}

namespace {
// The direction model of each axis (docs/runtime.md step 4), in this order of trust:
//  1. the CNC's programmed direction, where the link gives one: taken on every usable read, moving
//     or standing (the program's direction is never moved by the compensation's own nudges);
//  2. else the servo direction while the CNC reports the axis moving (any report with
//     direction_only_while_moving off);
//  3. else, on every new good read, the position against the turning point: the farthest position
//     reached in the held direction since the model last switched. A position back from it by more
//     than direction_min_move_um (the noise) plus what the compensation output itself changed since
//     that read is a reversal, however few reads saw the move — also one read after a 5 mm overrun
//     and back. The servo direction of a standing axis is not taken here: at standstill it follows
//     the servo's µm dither and the compensation's nudges.
// At standstill the compensation's own µm nudges stay below the threshold and never flip the model.
void UpdateDirections(const StepModel& model, StepState& state, const CncSnapshot& cs, bool link_usable, bool new_read) {
  const CompensatorOptions& o = model.options;
  for (std::size_t i = 0; i < model.axes.size(); ++i) {
    const hw::AxisState& as = cs.axes[i];
    Direction& dir = state.direction[i];
    int told = 0;  // the direction the CNC tells this read (1., 2.); 0: none
    if (link_usable) {
      if (as.programmed_direction != 0) told = as.programmed_direction;
      else if (as.moving || !o.direction_only_while_moving) told = as.servo_direction;
    }
    if (told != 0) dir = told > 0 ? Direction::kForward : Direction::kReverse;
    if (!new_read) continue;
    StepState::LastRead& last = state.last_read[i];
    const double position_mm = model.axes[i].ModelPositionMm(as.position_mm);
    const double q = model.shaping.empty() ? model.axes[i].PhysicalQuantumUm() : model.shaping[i].quantum_um;
    const double held_um = OutputUm(state.shaper[i], q);
    if (std::isfinite(position_mm)) {
      const double sign = dir == Direction::kForward ? 1.0 : -1.0;
      const double beyond_um = sign * (position_mm - last.turn_position_mm) * 1000;  // NaN before the first read
      const double own_um = std::max(std::fabs(held_um - last.turn_held_um),
                                     std::fabs(last.held_um - last.turn_held_before_um));
      const bool reversed = told == 0 && -beyond_um > o.direction_min_move_um + own_um;
      if (reversed) dir = dir == Direction::kForward ? Direction::kReverse : Direction::kForward;
      // A new turning point: here, when the CNC told the direction, at a reversal, and on every
      // read that went farther in the held direction.
      if (told != 0 || reversed || !(beyond_um <= 0)) {
        last.turn_position_mm = position_mm;
        last.turn_held_um = held_um;
        last.turn_held_before_um = last.held_um;
      }
    }
    last.held_um = held_um;
  }
}
}  // namespace

void Step(const StepModel& model, StepState& state, const StepInputs& in, StepOutputs& out) {
  const CompensatorOptions& o = model.options;
  ++state.cycle;
  std::uint32_t alarms = 0;
  if (!model.bound) alarms |= kAlarmNoModel;

  const bool temps_ok = ConditionTemperatures(o.sensor, in.temperatures, in.now_s, state, out, alarms);
  bool read_ok = false;
  const std::uint64_t sequence_before = state.cnc_sequence;
  const bool link_usable = TakeCncSnapshot(model, in.cnc, in.now_s, state, read_ok, alarms);
  const bool new_read = read_ok && in.cnc->sequence != sequence_before;
  for (std::size_t i = 0; i < state.model_position_mm.size(); ++i)
    state.model_position_mm[i] = link_usable && i < model.axes.size()
                                     ? model.axes[i].ModelPositionMm(in.cnc->axes[i].position_mm)
                                     : std::nan("");
  if (link_usable || new_read) UpdateDirections(model, state, *in.cnc, link_usable, new_read);
  if (model.bound)
    AdvanceModelDynamics(*model.bound, out.channels, state.machine.coolant, in.now_s, state.dynamics,
                         state.model_position_mm);

  for (std::size_t i = 0; i < model.axes.size(); ++i) {
    const AxisInterface& ai = model.axes[i];
    AxisStatus& st = out.axes[i];
    st.prediction = model::Prediction{};
    st.thermal_used = false;
    st.fallback_model = -1;
    st.fallbacks_averaged = 0;
    std::uint32_t axis_alarms = 0;  // this axis's own, kept with it so a user is told which axis
    double desired = DesiredCorrection(model, state, in, i, link_usable, out, axis_alarms);
    // The additional error term (error sign): the correction gets its negative, before the shaper.
    st.extra_error_um = 0;
    if (st.enabled && i < in.extra_error_um.size() && std::isfinite(in.extra_error_um[i])) {
      st.extra_error_um = in.extra_error_um[i];
      desired -= st.extra_error_um;
    }
    const ShaperLimits limits = model.shaping.empty() ? AxisShaperLimits(o, ai) : model.shaping[i];
    st.clamped = std::fabs(desired) > limits.options.max_correction_um;
    if (st.clamped) axis_alarms |= kAlarmCorrectionClamped;
    st.alarms = axis_alarms;
    alarms |= axis_alarms;
    st.desired_um = desired;
    out.proposed[i] = state.outstanding ? state.pending[i] : ShapeOutput(state.shaper[i], desired, limits);
    out.command.correction_um[i] = ai.CncCorrectionUm(OutputUm(out.proposed[i], limits.quantum_um));
  }
  out.command.sequence = state.outstanding ? state.outstanding : state.cycle;

  CycleStatus& s = out.status;
  s.cycle = state.cycle;
  s.time_s = in.now_s;
  s.alarms = alarms;
  s.link_read_ok = read_ok;
  s.temperatures_ok = temps_ok;
  s.temperature_age_s = in.temperatures && in.temperatures->sequence ? in.now_s - in.temperatures->sampled_at_s : 0;
  s.cnc_age_s = in.cnc && in.cnc->sequence ? in.now_s - in.cnc->sampled_at_s : 0;
  s.coolant = state.machine.coolant;
  s.model_id = model.bound ? model.bound->id : 0;
}

namespace {
// The status's outputs: what the CNC holds (the shaper's state after the write phase).
void ReportOutputs(const StepModel& model, const StepState& state, StepOutputs& out) {
  for (std::size_t i = 0; i < model.axes.size(); ++i) {
    const double q = model.shaping.empty() ? model.axes[i].PhysicalQuantumUm() : model.shaping[i].quantum_um;
    out.axes[i].output_um = OutputUm(state.shaper[i], q);
    out.axes[i].written_um = model.axes[i].CncCorrectionUm(out.axes[i].output_um);
  }
}
}  // namespace

void CommitWrite(const StepModel& model, StepState& state, bool write_ok, StepOutputs& out) {
  if (write_ok) {
    for (std::size_t i = 0; i < model.axes.size(); ++i) state.shaper[i] = out.proposed[i];
  } else {
    out.status.alarms |= kAlarmLinkWrite;
  }
  ReportOutputs(model, state, out);
  out.status.write_ok = write_ok;
}

void AwaitWrite(const StepModel& model, StepState& state, StepOutputs& out) {
  if (state.outstanding == 0) {
    state.outstanding = out.command.sequence;
    for (std::size_t i = 0; i < model.axes.size(); ++i) state.pending[i] = out.proposed[i];
  }
  ReportOutputs(model, state, out);
  out.status.write_ok = !(out.status.alarms & kAlarmLinkWrite);
}

}  // namespace trueaxis::runtime
