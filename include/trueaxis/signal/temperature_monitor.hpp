#pragma once
// TemperatureMonitor: all temperature channels of one machine, processed
// every cycle (seed 000 "溫度信號處理模塊"): calibration, de-noising
// (ChannelFilter) and fault detection with a status per channel.
//
//   TemperatureMonitor mon({"ambient", "x_nut", "x_bearing"}, options);   // allocates here only
//   mon.SetCalibration(cal_set);                                          // optional
//   every cycle:  source.Read(raw);  mon.Update(now_s, raw);              // no allocation, no lock
//                 (or mon.MarkSourceFailed(now_s) when Read() returned false)
//                 const auto& r = mon.reading(i);  if (r.usable()) use r.filtered_c; else fall back
//
// Fault rules (docs/signal.md): a detection must persist `confirm_samples`
// samples to raise a status, and the channel must be clean for
// `recover_samples` samples to return to ok — the status does not chatter.
// While a channel is faulty its `last_good_c` keeps the last value that was ok.
// This is the one place where temperatures are judged: the runtime's step takes the verdict
// (Judge, JudgedTemperature) and adds only the snapshot's freshness and how long a faulted
// channel's last good value is held (docs/runtime.md).
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/calibration.hpp"
#include "trueaxis/signal/channel_filter.hpp"
#include "trueaxis/signal/channel_status.hpp"
#include "trueaxis/signal/judged_temperature.hpp"

namespace trueaxis::signal {

struct FaultOptions {
  double min_plausible_c = -10.0;   // below: under_range (shorted sensor)
  double max_plausible_c = 80.0;    // above: over_range (open sensor)
  double range_hysteresis_c = 0.5;  // must come back inside by this much to clear
  // A raw reading within this fraction of the channel's measuring range (SetMeasuringRange: the
  // sensor kind's transmitter span, the module's input range) from either end is the chain's rail,
  // not a temperature: over_range / under_range, whatever the plausible limits above say.
  double rail_fraction = 0.005;
  double max_rate_c_per_s = 0.5;    // on the filtered value; machine structures move < 0.05 °C/s; 0: no rate rule
  // Noise allowance of the rate rule for values judged as read (the filter's low-pass off):
  // rate_of_change when |Δ| > max_rate_c_per_s·Δt + this. A low-passed value needs none.
  double rate_allowance_c = 0.0;
  double stuck_window_s = 300.0;    // evaluation window for "stuck"
  // Own raw span at or below this = "no change". 0 = bit-identical readings
  // only (a frozen register or hung module): real quiet sensors drift by
  // hundredths over minutes (FL_THERMAL t6/t7 stay within 0.02 °C for 7 min
  // while others warm 0.3 °C), so a non-zero band flags healthy channels.
  double stuck_band_c = 0.0;
  double others_moving_c = 0.3;     // ... while another healthy channel's filtered value moved at least this much
  double max_disagreement_c = 3.0;  // from the median of its neighbour group
  double reset_filter_after_s = 10.0;  // a channel that missed samples (fault) for this long restarts its filter
  // No sample at all for this long (the machine or the reader was switched off): the filter
  // restarts at the next sample, whose value is then taken as it is — a median window of
  // yesterday's values would reject today's first readings as spikes and hold the old value.
  double restart_after_gap_s = 600.0;
  double stale_after_s = 2.0;       // MarkSourceFailed: no data this long -> no_data
  int confirm_samples = 3;
  int recover_samples = 20;
  bool IsValid(std::string* why) const;
};

struct MonitorOptions {
  FilterOptions filter;
  FaultOptions faults;
  // Channels that should read alike (e.g. two ambient sensors, nut and
  // bearing of one axis when they are a few cm apart). Names must exist.
  std::vector<std::vector<std::string>> neighbour_groups;
  bool IsValid(std::string* why) const;
};

struct ChannelReading {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double time_s = kNaN;        // time of the last Update that delivered this channel
  double raw_c = kNaN;         // as delivered by the source
  double calibrated_c = kNaN;  // after the sensor's calibration
  double filtered_c = kNaN;    // after spike rejection, median and low-pass
  double last_good_c = kNaN;   // filtered value of the last sample whose status was ok
  ChannelStatus status = ChannelStatus::kNoData;    // after hysteresis: what to act on
  ChannelStatus detected = ChannelStatus::kNoData;  // this sample's raw detection
  bool spike_rejected = false;
  bool status_changed = false;  // status differs from the previous sample's (raise/clear an alarm)
  bool usable() const { return status == ChannelStatus::kOk; }
};

class TemperatureMonitor {
 public:
  // Throws std::invalid_argument when options are invalid or a neighbour
  // group names an unknown channel.
  TemperatureMonitor(std::vector<std::string> channel_names, MonitorOptions options = {});

  std::size_t ChannelCount() const { return channels_.size(); }
  const std::string& ChannelName(std::size_t i) const { return names_[i]; }
  // Index of a channel, or -1.
  int FindChannel(std::string_view name) const;

  void SetCalibration(std::size_t channel, const SensorCalibration& cal);
  // Applies every sensor of `set` that names a channel here; returns the
  // names in the set that match no channel (so callers can warn).
  std::vector<std::string> SetCalibration(const CalibrationSet& set);

  // One cycle. raw[i] belongs to channel i; raw.size() must be ChannelCount()
  // (missing channels count as no data). No allocation, no lock.
  void Update(double time_s, std::span<const hw::RawTemperature> raw);
  // The channel's measuring range (hw::TemperatureSource::ChannelMeasuringRange); a raw reading at
  // its rail is a fault (FaultOptions::rail_fraction). Does not allocate.
  void SetMeasuringRange(std::size_t channel, const hw::MeasuringRange& range) { channels_.at(channel).range = range; }
  // The source could not be read this cycle.
  void MarkSourceFailed(double time_s);

  const ChannelReading& reading(std::size_t i) const { return channels_[i].reading; }
  // The verdict of the latest Update / MarkSourceFailed per channel (out[i] for channel i; at most
  // ChannelCount() entries): what the compensation loop takes. No allocation.
  void Judge(std::span<JudgedTemperature> out) const;
  std::size_t SpikeCount(std::size_t i) const { return channels_[i].spikes; }
  bool AllUsable() const;
  const MonitorOptions& options() const { return options_; }
  std::string BriefReport() const;  // one line per channel: name, value, status

 private:
  struct Channel {
    ChannelFilter filter;
    SensorCalibration calibration;
    ChannelReading reading;
    hw::MeasuringRange range;  // unknown (±inf) until SetMeasuringRange
    ChannelStatus candidate = ChannelStatus::kOk;
    int confirm_count = 0;
    int clean_count = 0;
    double last_fed_time_s = ChannelReading::kNaN;
    double last_filtered_c = ChannelReading::kNaN;
    // Stuck window bookkeeping.
    double win_raw_min = 0, win_raw_max = 0, win_filt_min = 0, win_filt_max = 0;
    int win_samples = 0;
    bool stuck = false;
    double stuck_value_c = 0;
    bool disagrees = false;
    std::size_t spikes = 0;
  };

  ChannelStatus DetectInstant(Channel& ch, const hw::RawTemperature& raw, double time_s);
  void EvaluateStuckWindow();
  void EvaluateNeighbourGroups();
  void ApplyHysteresis(Channel& ch, ChannelStatus detected);

  std::vector<std::string> names_;
  MonitorOptions options_;
  std::vector<Channel> channels_;
  std::vector<std::vector<std::size_t>> groups_;
  std::vector<ChannelStatus> detected_scratch_;  // sized once
  std::vector<double> group_scratch_;            // sized once (largest group)
  double window_start_s_ = ChannelReading::kNaN;
  double last_data_time_s_ = ChannelReading::kNaN;
};

}  // namespace trueaxis::signal
