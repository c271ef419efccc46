#include "trueaxis/signal/temperature_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::signal {

bool FaultOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (!(max_plausible_c > min_plausible_c)) return fail("max_plausible_c must be greater than min_plausible_c");
  if (!(range_hysteresis_c >= 0)) return fail("range_hysteresis_c must be >= 0");
  if (!(rail_fraction >= 0 && rail_fraction < 0.5)) return fail("rail_fraction must be in [0, 0.5)");
  if (!(max_rate_c_per_s >= 0)) return fail("max_rate_c_per_s must be >= 0 (0: no rate rule)");
  if (!(rate_allowance_c >= 0)) return fail("rate_allowance_c must be >= 0");
  if (!(stuck_window_s > 0)) return fail("stuck_window_s must be > 0");
  if (!(stuck_band_c >= 0)) return fail("stuck_band_c must be >= 0");
  if (!(others_moving_c > stuck_band_c)) return fail("others_moving_c must be greater than stuck_band_c");
  if (!(max_disagreement_c > 0)) return fail("max_disagreement_c must be > 0");
  if (!(reset_filter_after_s > 0)) return fail("reset_filter_after_s must be > 0");
  if (!(restart_after_gap_s > 0)) return fail("restart_after_gap_s must be > 0");
  if (!(stale_after_s >= 0)) return fail("stale_after_s must be >= 0");
  if (confirm_samples < 1) return fail("confirm_samples must be >= 1");
  if (recover_samples < 1) return fail("recover_samples must be >= 1");
  return true;
}

bool MonitorOptions::IsValid(std::string* why) const {
  std::string inner;
  if (!filter.IsValid(&inner)) {
    if (why) *why = "filter: " + inner;
    return false;
  }
  if (!faults.IsValid(&inner)) {
    if (why) *why = "faults: " + inner;
    return false;
  }
  for (const auto& g : neighbour_groups) {
    if (g.size() < 2) {
      if (why) *why = "a neighbour group needs at least 2 channels";
      return false;
    }
  }
  return true;
}

TemperatureMonitor::TemperatureMonitor(std::vector<std::string> channel_names, MonitorOptions options)
    : names_(std::move(channel_names)), options_(std::move(options)) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("TemperatureMonitor options: " + why);
  for (std::size_t i = 0; i < names_.size(); ++i)
    for (std::size_t j = i + 1; j < names_.size(); ++j)
      if (names_[i] == names_[j]) throw std::invalid_argument("TemperatureMonitor: channel '" + names_[i] + "' given twice");
  channels_.resize(names_.size());
  for (auto& ch : channels_) ch.filter = ChannelFilter(options_.filter);
  std::size_t largest = 0;
  for (const auto& g : options_.neighbour_groups) {
    std::vector<std::size_t> idx;
    for (const auto& name : g) {
      const int i = FindChannel(name);
      if (i < 0) throw std::invalid_argument("TemperatureMonitor: neighbour group names unknown channel '" + name + "'");
      idx.push_back(static_cast<std::size_t>(i));
    }
    largest = std::max(largest, idx.size());
    groups_.push_back(std::move(idx));
  }
  detected_scratch_.assign(channels_.size(), ChannelStatus::kNoData);
  group_scratch_.assign(largest, 0.0);
}

int TemperatureMonitor::FindChannel(std::string_view name) const {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return static_cast<int>(i);
  return -1;
}

void TemperatureMonitor::SetCalibration(std::size_t channel, const SensorCalibration& cal) {
  auto& ch = channels_.at(channel);
  ch.calibration = cal;
  // The calibrated value steps: restart the filter so the step is not taken
  // for an implausible rate of change.
  ch.filter.Reset();
  ch.last_filtered_c = ChannelReading::kNaN;
}

std::vector<std::string> TemperatureMonitor::SetCalibration(const CalibrationSet& set) {
  std::vector<std::string> unknown;
  for (const auto& [name, fit] : set.sensors) {
    const int i = FindChannel(name);
    if (i < 0) unknown.push_back(name);
    else SetCalibration(static_cast<std::size_t>(i), fit.calibration);
  }
  return unknown;
}

bool TemperatureMonitor::AllUsable() const {
  return std::all_of(channels_.begin(), channels_.end(), [](const Channel& c) { return c.reading.usable(); });
}

ChannelStatus TemperatureMonitor::DetectInstant(Channel& ch, const hw::RawTemperature& raw, double time_s) {
  const FaultOptions& f = options_.faults;
  ChannelReading& r = ch.reading;
  // Did the previous Update skip feeding this channel (a fault)? Only then can
  // a long gap mean stale filter state; slow regular sampling is not a gap.
  const bool missed_samples = !std::isnan(ch.last_fed_time_s) && ch.last_fed_time_s != r.time_s;
  r.time_s = time_s;
  r.raw_c = raw.temp_c;
  r.spike_rejected = false;
  if (raw.hardware_fault || !std::isfinite(raw.temp_c)) {
    r.calibrated_c = std::isfinite(raw.temp_c) ? ch.calibration.Apply(raw.temp_c) : ChannelReading::kNaN;
    return ChannelStatus::kHardwareFault;
  }
  const double cal = ch.calibration.Apply(raw.temp_c);
  r.calibrated_c = cal;
  if (ch.range.known()) {  // the measuring chain's own rails, on the raw value it reports
    const double rail = f.rail_fraction * (ch.range.max_c - ch.range.min_c);
    double rail_lo = ch.range.min_c + rail, rail_hi = ch.range.max_c - rail;
    if (r.status == ChannelStatus::kUnderRange) rail_lo += f.range_hysteresis_c;
    if (r.status == ChannelStatus::kOverRange) rail_hi -= f.range_hysteresis_c;
    if (raw.temp_c <= rail_lo) return ChannelStatus::kUnderRange;
    if (raw.temp_c >= rail_hi) return ChannelStatus::kOverRange;
  }
  double lo = f.min_plausible_c, hi = f.max_plausible_c;
  if (r.status == ChannelStatus::kUnderRange) lo += f.range_hysteresis_c;
  if (r.status == ChannelStatus::kOverRange) hi -= f.range_hysteresis_c;
  if (cal < lo) return ChannelStatus::kUnderRange;
  if (cal > hi) return ChannelStatus::kOverRange;

  // A plausible sample: feed the filter. Faulty samples above never reach it,
  // so the filter state stays clean for when the channel recovers.
  double dt = 0;
  if (!std::isnan(ch.last_fed_time_s)) {
    dt = time_s - ch.last_fed_time_s;
    if ((missed_samples && dt > f.reset_filter_after_s) || dt > f.restart_after_gap_s) {
      ch.filter.Reset();
      ch.last_filtered_c = ChannelReading::kNaN;
      dt = 0;
    }
  }
  const auto out = ch.filter.Process(cal, dt);
  ch.last_fed_time_s = time_s;
  r.filtered_c = out.value_c;
  r.spike_rejected = out.spike_rejected;
  if (out.spike_rejected) ++ch.spikes;

  if (ch.win_samples == 0) {
    ch.win_raw_min = ch.win_raw_max = cal;
    ch.win_filt_min = ch.win_filt_max = out.value_c;
  } else {
    ch.win_raw_min = std::min(ch.win_raw_min, cal);
    ch.win_raw_max = std::max(ch.win_raw_max, cal);
    ch.win_filt_min = std::min(ch.win_filt_min, out.value_c);
    ch.win_filt_max = std::max(ch.win_filt_max, out.value_c);
  }
  ++ch.win_samples;

  const double previous = ch.last_filtered_c;
  ch.last_filtered_c = out.value_c;
  if (!std::isnan(previous) && dt > 0 && f.max_rate_c_per_s > 0) {
    const double limit = r.status == ChannelStatus::kRateOfChange ? 0.5 * f.max_rate_c_per_s : f.max_rate_c_per_s;
    // The allowance is for the noise of values judged as read; a low-passed value has none to allow for.
    const double allowance = options_.filter.lowpass_time_constant_s > 0 ? 0.0 : f.rate_allowance_c;
    if (std::abs(out.value_c - previous) > limit * dt + allowance) return ChannelStatus::kRateOfChange;
  }
  return ChannelStatus::kOk;
}

void TemperatureMonitor::EvaluateStuckWindow() {
  const FaultOptions& f = options_.faults;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    Channel& ch = channels_[i];
    if (ch.win_samples < 2 || ch.stuck) continue;
    if (ch.win_raw_max - ch.win_raw_min > f.stuck_band_c) continue;
    bool others_moved = false;
    for (std::size_t j = 0; j < channels_.size() && !others_moved; ++j) {
      // Only a healthy channel's movement counts: a channel that jumped
      // because it is faulty says nothing about the machine warming.
      if (j == i || channels_[j].win_samples < 2 || channels_[j].stuck ||
          channels_[j].reading.status != ChannelStatus::kOk)
        continue;
      others_moved = channels_[j].win_filt_max - channels_[j].win_filt_min >= f.others_moving_c;
    }
    if (others_moved) {
      ch.stuck = true;
      ch.stuck_value_c = 0.5 * (ch.win_raw_min + ch.win_raw_max);
    }
  }
  for (auto& ch : channels_) ch.win_samples = 0;
}

void TemperatureMonitor::EvaluateNeighbourGroups() {
  const FaultOptions& f = options_.faults;
  for (auto& ch : channels_) ch.disagrees = false;
  for (const auto& group : groups_) {
    std::size_t n = 0;
    for (std::size_t idx : group)
      if (detected_scratch_[idx] == ChannelStatus::kOk && !channels_[idx].stuck)
        group_scratch_[n++] = channels_[idx].reading.filtered_c;
    if (n < 2) continue;
    // A pair cannot say which one is wrong: both are flagged when they differ
    // by more than the limit. Three or more vote through the median.
    const double centre = n == 2 ? 0.0 : MedianOf(group_scratch_.data(), static_cast<int>(n));
    double pair_diff = n == 2 ? std::abs(group_scratch_[0] - group_scratch_[1]) : 0.0;
    for (std::size_t idx : group) {
      Channel& ch = channels_[idx];
      if (detected_scratch_[idx] != ChannelStatus::kOk || ch.stuck) continue;
      const double dev = n == 2 ? pair_diff : std::abs(ch.reading.filtered_c - centre);
      const double limit = ch.reading.status == ChannelStatus::kDisagreement ? 0.7 * f.max_disagreement_c
                                                                               : f.max_disagreement_c;
      if (dev > limit) ch.disagrees = true;
    }
  }
}

void TemperatureMonitor::ApplyHysteresis(Channel& ch, ChannelStatus detected) {
  ChannelReading& r = ch.reading;
  const ChannelStatus before = r.status;
  r.detected = detected;
  if (detected == ChannelStatus::kNoData) {
    r.status = ChannelStatus::kNoData;
    ch.confirm_count = 0;
    ch.clean_count = 0;
  } else if (detected != ChannelStatus::kOk) {
    ch.clean_count = 0;
    if (detected == ch.candidate) ++ch.confirm_count;
    else {
      ch.candidate = detected;
      ch.confirm_count = 1;
    }
    if (ch.confirm_count >= options_.faults.confirm_samples) r.status = detected;
  } else {
    ch.candidate = ChannelStatus::kOk;
    ch.confirm_count = 0;
    if (r.status == ChannelStatus::kNoData) {
      r.status = ChannelStatus::kOk;
    } else if (r.status != ChannelStatus::kOk && ++ch.clean_count >= options_.faults.recover_samples) {
      r.status = ChannelStatus::kOk;
      ch.clean_count = 0;
    }
  }
  if (r.status == ChannelStatus::kOk) r.last_good_c = r.filtered_c;
  r.status_changed = r.status != before;
}

void TemperatureMonitor::Update(double time_s, std::span<const hw::RawTemperature> raw) {
  last_data_time_s_ = time_s;
  for (std::size_t i = 0; i < channels_.size(); ++i)
    detected_scratch_[i] = i < raw.size() ? DetectInstant(channels_[i], raw[i], time_s) : ChannelStatus::kNoData;

  if (std::isnan(window_start_s_)) window_start_s_ = time_s;
  if (time_s - window_start_s_ >= options_.faults.stuck_window_s) {
    EvaluateStuckWindow();
    window_start_s_ = time_s;
  }
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    Channel& ch = channels_[i];
    if (ch.stuck && detected_scratch_[i] == ChannelStatus::kOk &&
        std::abs(ch.reading.calibrated_c - ch.stuck_value_c) > options_.faults.stuck_band_c)
      ch.stuck = false;  // it moves again
  }
  EvaluateNeighbourGroups();
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    Channel& ch = channels_[i];
    ChannelStatus d = detected_scratch_[i];
    if (d == ChannelStatus::kOk && ch.stuck) d = ChannelStatus::kStuck;
    else if (d == ChannelStatus::kOk && ch.disagrees) d = ChannelStatus::kDisagreement;
    ApplyHysteresis(ch, d);
  }
}

void TemperatureMonitor::MarkSourceFailed(double time_s) {
  const bool stale = std::isnan(last_data_time_s_) || time_s - last_data_time_s_ >= options_.faults.stale_after_s;
  for (auto& ch : channels_) {
    if (stale) ApplyHysteresis(ch, ChannelStatus::kNoData);
    else ch.reading.status_changed = false;
  }
}

void TemperatureMonitor::Judge(std::span<JudgedTemperature> out) const {
  for (std::size_t i = 0; i < out.size() && i < channels_.size(); ++i) {
    const ChannelReading& r = channels_[i].reading;
    out[i] = {r.usable() ? r.filtered_c : JudgedTemperature::kNaN, r.raw_c, r.status};
  }
}

std::string TemperatureMonitor::BriefReport() const {
  std::string out;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const auto& r = channels_[i].reading;
    out += fmt::format("{:<16} {:>9.3f} °C  {}\n", names_[i], r.filtered_c, ChannelStatusName(r.status));
  }
  return out;
}

}  // namespace trueaxis::signal
