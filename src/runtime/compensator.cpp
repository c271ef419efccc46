#include "trueaxis/runtime/compensator.hpp"

#include <cmath>
#include <stdexcept>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/thermal_state.hpp"

namespace trueaxis::runtime {

static_assert(kMaxKeySensors <= model::kMaxStateKeys, "the model's thermal state must hold every key sensor");

std::string AlarmNames(std::uint32_t alarms) {
  static const char* const kNames[] = {"sensor_held",       "sensor_fallback",    "temperature_source",
                                       "link_read",         "link_write",         "no_model_for_axis",
                                       "correction_clamped", "no_model",          "model_extrapolated"};
  std::string out;
  for (int i = 0; i < 9; ++i) {
    if (alarms & (1u << i)) {
      if (!out.empty()) out += '|';
      out += kNames[i];
    }
  }
  return out;
}

Compensator::Compensator(CompensatorOptions options, std::vector<AxisInterface> axes, std::vector<std::string> channel_names)
    : options_(std::move(options)), axes_(std::move(axes)), channel_names_(std::move(channel_names)) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("compensator options: " + why);
  for (const auto& a : axes_)
    if (!a.IsValid(&why)) throw std::invalid_argument("axis interface: " + why);
  const std::size_t n = axes_.size(), m = channel_names_.size();
  axis_enabled_ = std::make_unique<std::atomic<bool>[]>(n);
  for (std::size_t i = 0; i < n; ++i) axis_enabled_[i].store(axes_[i].enabled);
  raw_.resize(m);
  last_good_c_.assign(m, std::nan(""));
  last_good_time_s_.assign(m, 0);
  has_good_.assign(m, 0);
  channels_.resize(m);
  axis_states_.resize(n);
  last_direction_.assign(n, Direction::kForward);
  shaper_.resize(n);
  proposed_.resize(n);
  write_buffer_.assign(n, 0);
  axis_status_.resize(n);
  thermal_state_.resize(n);
  lag_time_s_.assign(n, 0);
  lag_model_id_.assign(n, 0);
  good_reads_in_row_ = options_.link_recovery_cycles;  // start as if connected; the first read decides
  status_.axes = axis_status_;
  status_.channels = channels_;
}

std::unique_ptr<Compensator> Compensator::ForHardware(const CompensatorOptions& options, const hw::CncLink& link,
                                                      const hw::TemperatureSource& source,
                                                      const std::vector<AxisInterface>& interfaces) {
  std::vector<AxisInterface> axes;
  for (std::size_t i = 0; i < link.AxisCount(); ++i) {
    AxisInterface a;
    a.axis = link.AxisName(i);
    for (const auto& given : interfaces)
      if (given.axis == a.axis) a = given;
    axes.push_back(a);
  }
  std::vector<std::string> channels;
  for (std::size_t i = 0; i < source.ChannelCount(); ++i) channels.push_back(source.ChannelName(i));
  return std::make_unique<Compensator>(options, std::move(axes), std::move(channels));
}

void Compensator::PublishModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label) {
  auto bound = BindModel(std::move(model), label, axes_, channel_names_, options_.channel_map);
  bound->id = next_model_id_.fetch_add(1);
  exchange_.Publish(std::move(bound));
}

void Compensator::ConditionTemperatures(bool read_ok, double now_s) {
  const SensorFaultPolicy& p = options_.sensor;
  for (std::size_t i = 0; i < raw_.size(); ++i) {
    const double t = raw_[i].temp_c;
    bool valid = read_ok && !raw_[i].hardware_fault && std::isfinite(t) && t >= p.min_valid_c && t <= p.max_valid_c;
    if (valid && has_good_[i] && p.max_rate_c_per_s > 0) {
      const double allowed = p.max_rate_c_per_s * (now_s - last_good_time_s_[i]) + p.rate_allowance_c;
      valid = std::fabs(t - last_good_c_[i]) <= allowed;
    }
    ChannelStatus& c = channels_[i];
    c.raw_c = read_ok ? t : std::nan("");
    if (valid) {
      last_good_c_[i] = t;
      last_good_time_s_[i] = now_s;
      has_good_[i] = 1;
      c.value_c = t;
      c.health = ChannelHealth::kOk;
    } else if (has_good_[i] && now_s - last_good_time_s_[i] <= p.hold_last_good_s) {
      c.value_c = last_good_c_[i];
      c.health = ChannelHealth::kHeld;
    } else {
      c.value_c = std::nan("");
      c.health = ChannelHealth::kLost;
    }
  }
}

const CycleStatus& Compensator::RunCycle(hw::CncLink& link, hw::TemperatureSource& source, double now_s) {
  ++cycle_;
  std::uint32_t alarms = 0;
  const BoundModel* bound = exchange_.Acquire();
  if (!bound) alarms |= kAlarmNoModel;

  const bool temps_ok = source.Read(raw_);
  if (!temps_ok) alarms |= kAlarmTemperatureSource;
  ConditionTemperatures(temps_ok, now_s);

  const bool read_ok = link.Read(axis_states_, cnc_state_);
  good_reads_in_row_ = read_ok ? good_reads_in_row_ + 1 : 0;
  const bool link_usable = read_ok && good_reads_in_row_ >= options_.link_recovery_cycles;
  if (!link_usable) alarms |= kAlarmLinkRead;

  const bool global_on = enabled_.load(std::memory_order_relaxed);
  const bool cnc_on = !options_.follow_cnc_enable || cnc_state_.compensation_enabled;
  const OutputShaperOptions& so = options_.shaper;

  // The model's thermal state (model::AdvanceThermalState: lagged / observed key temperatures):
  // advanced every cycle for every axis with a model, enabled or not, so it tracks the machine's
  // history and not only the time compensation was on.
  for (std::size_t i = 0; bound && i < axes_.size(); ++i) {
    const BoundAxis& ba = bound->axes[i];
    if (!ba.has_model) continue;
    bool fresh = lag_model_id_[i] != bound->id;
    for (std::size_t k = 0; k < ba.key_channel.size(); ++k) {
      const ChannelStatus& c = channels_[static_cast<std::size_t>(ba.key_channel[k])];
      if (c.health == ChannelHealth::kLost) fresh = true;  // restart at the readings once they return
      key_raw_[k] = c.value_c;
    }
    const double ambient =
        ba.ambient_channel >= 0 ? channels_[static_cast<std::size_t>(ba.ambient_channel)].value_c : std::nan("");
    if (fresh) thermal_state_[i].valid = false;
    model::AdvanceThermalState(ba.model, thermal_state_[i],
                               {std::span<const double>(key_raw_, ba.key_channel.size()), ambient, cnc_state_.coolant},
                               now_s - lag_time_s_[i]);
    lag_time_s_[i] = now_s;
    // A lost key leaves the state marked stale (id 0), so the next good cycle restarts the filter.
    bool any_lost = false;
    for (std::size_t k = 0; k < ba.key_channel.size(); ++k)
      any_lost = any_lost || channels_[static_cast<std::size_t>(ba.key_channel[k])].health == ChannelHealth::kLost;
    lag_model_id_[i] = any_lost ? 0 : bound->id;
  }

  for (std::size_t i = 0; i < axes_.size(); ++i) {
    const AxisInterface& ai = axes_[i];
    AxisStatus& st = axis_status_[i];
    st.prediction = model::Prediction{};
    st.thermal_used = false;
    double desired = 0;
    if (!link_usable) {
      desired = options_.link_loss == LinkLossPolicy::kHold ? std::nan("") : 0.0;
      st.enabled = false;
    } else {
      const hw::AxisState& as = axis_states_[i];
      if (as.moving || !options_.direction_only_while_moving) {
        if (as.servo_direction > 0) last_direction_[i] = Direction::kForward;
        else if (as.servo_direction < 0) last_direction_[i] = Direction::kReverse;
      }
      st.cnc_position_mm = as.position_mm;
      st.model_position_mm = ai.ModelPositionMm(as.position_mm);
      st.direction = last_direction_[i];
      st.enabled = global_on && cnc_on && axis_enabled_[i].load(std::memory_order_relaxed);
      const BoundAxis* ba = bound ? &bound->axes[i] : nullptr;
      if (st.enabled && ba && !ba->has_model) alarms |= kAlarmNoModelForAxis;
      if (st.enabled && ba && ba->has_model) {
        bool keys_ok = true;
        for (std::size_t k = 0; k < ba->key_channel.size(); ++k) {
          const ChannelStatus& c = channels_[static_cast<std::size_t>(ba->key_channel[k])];
          if (c.health == ChannelHealth::kHeld) alarms |= kAlarmSensorHeld;
          if (c.health == ChannelHealth::kLost) keys_ok = false;
          key_temps_[k] = thermal_state_[i].key_c[k];  // = c.value_c when the model has no lag
        }
        double ambient = std::nan("");
        if (ba->ambient_channel >= 0) {
          const ChannelStatus& c = channels_[static_cast<std::size_t>(ba->ambient_channel)];
          if (c.health == ChannelHealth::kHeld) alarms |= kAlarmSensorHeld;
          if (c.health == ChannelHealth::kLost) alarms |= kAlarmSensorFallback;  // ambient adjustment dropped
          ambient = c.value_c;
        }
        if (!keys_ok) alarms |= kAlarmSensorFallback;
        if (!keys_ok && options_.sensor.fallback == SensorFallback::kZero) {
          desired = 0;
        } else {
          model::ThermalState ts{std::span<const double>(key_temps_, ba->key_channel.size()), ambient,
                                 cnc_state_.coolant, keys_ok};
          st.prediction = model::Predict(ba->model, st.model_position_mm, st.direction, ts);
          st.thermal_used = keys_ok;
          if (st.prediction.tan_beta_limited) alarms |= kAlarmModelExtrapolated;  // held at the fitted envelope
          desired = model::CorrectionUm(st.prediction);
          if (!std::isfinite(desired)) desired = 0;  // a broken model never drives the axis
        }
      }
    }
    OutputShaperOptions axis_so = so;  // a few doubles on the stack: no allocation
    if (!std::isnan(ai.max_correction_um)) axis_so.max_correction_um = ai.max_correction_um;
    st.clamped = std::fabs(desired) > axis_so.max_correction_um;
    if (st.clamped) alarms |= kAlarmCorrectionClamped;
    st.desired_um = desired;
    const double q = ai.PhysicalQuantumUm();
    proposed_[i] = ShapeOutput(shaper_[i], desired, q, axis_so);
    write_buffer_[i] = ai.CncCorrectionUm(OutputUm(proposed_[i], q));
  }

  const bool write_ok = link.WriteCompensation(write_buffer_);
  if (!write_ok) alarms |= kAlarmLinkWrite;
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    if (write_ok) shaper_[i] = proposed_[i];
    const double q = axes_[i].PhysicalQuantumUm();
    axis_status_[i].output_um = OutputUm(shaper_[i], q);
    axis_status_[i].written_um = axes_[i].CncCorrectionUm(axis_status_[i].output_um);
  }

  status_.cycle = cycle_;
  status_.time_s = now_s;
  status_.alarms = alarms;
  status_.link_read_ok = read_ok;
  status_.write_ok = write_ok;
  status_.temperatures_ok = temps_ok;
  status_.coolant = cnc_state_.coolant;
  status_.model_id = bound ? bound->id : 0;
  return status_;
}

}  // namespace trueaxis::runtime
