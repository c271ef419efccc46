#pragma once
// Seed 001 (tool thermal error): temperature-to-error has hysteresis — the
// error while heating differs from the error at the same temperature while
// cooling — so the temperature history is split into heating, steady and
// cooling intervals and each interval gets its own sub-model.
//
// Classification rule (the seed's own rule text is truncated in our copy;
// this one is ours, docs/thermal-models.md): the trend of a reference
// temperature (the mean of the reference sensors) is the slope of the
// least-squares line through its samples in the trailing window
// [t - window_s, t] — causal, so the runtime can classify as it goes.
//   slope >  +threshold_c_per_h  -> heating
//   slope <  -threshold_c_per_h  -> cooling
//   otherwise -> steady
// A sample whose window holds fewer than 3 samples or spans less than half
// of window_s (the start of a recording, or after a gap) is kStartUp: the
// trend is not known yet, and the all-data model predicts it.
// The fit widens the window to at least kMinWindowSteps sample steps when the
// recording's sample interval is coarse (with a warning), so a trend can be
// measured at any sample interval.
// Sub-models are linear/ridge models (linear_model.hpp) on the same sensor
// selection options; an interval with fewer than min_interval_samples
// training rows uses the all-data model instead (said in Describe()).
#include <string>
#include <vector>

#include "trueaxis/model/trend_window.hpp"
#include "trueaxis/thermal/linear_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::thermal {

inline constexpr int kMinWindowSteps = 6;

struct IntervalClassifierOptions {
  double window_s = 900.0;
  double threshold_c_per_h = 0.3;

  bool IsValid(std::string* why) const;
};

// Trailing-window least-squares slope of `reference_c` in °C per hour (0 where
// the window holds fewer than 3 samples).
std::vector<double> TemperatureTrendCPerH(const std::vector<double>& time_s, const Eigen::VectorXd& reference_c,
                                          double window_s);
std::vector<ThermalInterval> ClassifyIntervals(const std::vector<double>& time_s, const Eigen::VectorXd& reference_c,
                                               const IntervalClassifierOptions& options);

// The rule itself, from a trend and how much of the window it rests on: kStartUp while fewer
// than 3 samples or less than half a window of history, else heating / steady / cooling.
ThermalInterval ClassifyTrend(double trend_c_per_h, std::size_t samples, double span_s,
                              const IntervalClassifierOptions& options);

// The same rule, one sample at a time, for a real-time compensator: push each new (time,
// reference temperature) and get the interval. Allocation-free (model::TrendWindow's fixed
// bins); identical to ClassifyIntervals when samples are at least window_s / 128 apart, within
// one bin of it otherwise.
class IntervalTracker {
 public:
  explicit IntervalTracker(IntervalClassifierOptions options);
  // Time must increase; a sample not after the previous one resets the tracker.
  ThermalInterval Push(double time_s, double reference_c);
  double TrendCPerH() const { return window_.SlopePerH(); }
  void Reset() { window_.Reset(); }

 private:
  IntervalClassifierOptions options_;
  model::TrendWindow window_;
};

struct HysteresisFitOptions {
  LinearFitOptions sub_model;
  IntervalClassifierOptions classifier;
  std::vector<std::string> reference_sensors;  // empty: the sensors the all-data model selected
  int min_interval_samples = 30;

  bool IsValid(std::string* why) const;
};

class HysteresisThermalModel final : public ThermalErrorModel {
 public:
  HysteresisThermalModel() = default;
  HysteresisThermalModel(LinearThermalModel all_data, std::vector<LinearThermalModel> per_interval,
                         std::vector<bool> interval_fitted, std::vector<std::string> reference_sensors,
                         IntervalClassifierOptions classifier);

  std::string_view Kind() const override { return "hysteresis"; }
  const std::vector<std::string>& InputSensors() const override { return sensors_; }
  const std::vector<std::string>& Channels() const override { return all_data_.Channels(); }
  bool UsesInterval() const override { return true; }
  void Predict(const ThermalSample& sample, std::span<double> out_um) const override;
  std::vector<ThermalInterval> ClassifyRows(const ThermalSeries& series) const override;
  nlohmann::json ToJson() const override;
  std::string Describe() const override;

  const std::vector<std::string>& reference_sensors() const { return reference_; }
  const IntervalClassifierOptions& classifier() const { return classifier_; }
  static HysteresisThermalModel FromJson(const nlohmann::json& doc, const std::string& source, const std::string& path);

 private:
  void BuildMaps();
  LinearThermalModel all_data_;
  std::vector<LinearThermalModel> per_interval_;  // kThermalIntervalCount, by ThermalInterval
  std::vector<bool> fitted_;
  std::vector<std::string> reference_;
  IntervalClassifierOptions classifier_;
  std::vector<std::string> sensors_;
  std::vector<std::vector<int>> maps_;  // per sub-model (0..2 intervals, 3 all-data): its sensor -> our index
};

// Needs a series with time (InputError otherwise). `warnings` (optional) receives what the data
// could not support: a widened window, an interval with too few rows for its own sub-model.
HysteresisThermalModel FitHysteresisModel(const ThermalSeries& series, const HysteresisFitOptions& options,
                                          std::vector<std::string>* warnings = nullptr);

}  // namespace trueaxis::thermal
