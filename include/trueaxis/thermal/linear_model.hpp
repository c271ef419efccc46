#pragma once
// Multiple linear regression / ridge regression of each error channel on a
// few selected temperatures (docs/thermal-models.md):
//   e_c = intercept_c + sum_i k_ci * T_i      (µm, °C)
// Ridge: the penalty lambda * |k_std|^2 acts on standardised temperatures
// (so it does not depend on units); lambda = 0 is ordinary least squares.
// Sensors are chosen per channel by SelectSensors (sensor_selection.hpp).
#include <string>
#include <vector>

#include "trueaxis/thermal/sensor_selection.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::thermal {

struct LinearFitOptions {
  double ridge_lambda = 0.0;
  SensorSelectionOptions selection;
  // true: the inputs of each channel are chosen by time-ordered cross-validation on the training
  // rows (time_folds.hpp: forward chaining over one recording, leave one experiment out over
  // several) among the constant (the training mean, no input), 1, 2, 3, 4, 6, 8, 12, … and all of
  // the plain sensors, and — when the series holds lagged inputs — the same counts of sensors and
  // lags together and all inputs; with ridge_lambda > 0 all of a set also with the heavier penalties
  // 0.01 and 0.1. Candidates are ranked by the geometric mean of their folds'
  // held-out RMS; eligible are those not worse than the constant on the use-like rows (UseLikeBlocks:
  // the latest fold, or every experiment); the simplest eligible within 2 % of the best that is worse
  // than neither the constant nor all inputs is taken, averaged with the eligible candidates of its
  // kind (plain / with lags) that score as well within the folds' noise, each weighted by the inverse
  // square of its score (the average is linear: each coefficient the weighted mean of theirs),
  // shrunk toward the constant by the factor in
  // [0, 1] the use-like rows support, and kept only if it beats the constant there by more than one
  // standard error (blocks as replicates) — else the channel is the constant. selection.max_sensors
  // is then only an upper bound. The choice is the data's, per recording: four sensors can be far
  // worse than all of them on one machine and better on another, lags help on one and hurt on
  // another, and where no input beats the mean the channel is that constant.
  bool choose_count_by_cv = false;

  bool IsValid(std::string* why) const;
};

struct LinearChannel {
  std::string name;
  std::vector<int> inputs;          // indices into InputSensors()
  std::vector<double> k_um_per_c;   // parallel to inputs
  double intercept_um = 0;
  // How the inputs were chosen (choose_count_by_cv): the held-out RMS in µm per candidate, e.g.
  // "constant: 0.323; sensors 1: 0.512, 2: 0.307, all: 0.401; with lags 1: 0.498, …, all: 0.530",
  // and the candidate taken ("constant", "2 of the sensors", "all sensors and lags", …); empty when
  // the count was given.
  std::string count_cv, cv_choice;
  // The channel is the training mean alone: no input beat it on the cross-validation ("constant",
  // or "constant (… did not beat it beyond the noise …)").
  bool IsConstant() const { return inputs.empty() && cv_choice.rfind("constant", 0) == 0; }
};

class LinearThermalModel final : public ThermalErrorModel {
 public:
  LinearThermalModel() = default;
  LinearThermalModel(std::vector<std::string> input_sensors, std::vector<LinearChannel> channels, double ridge_lambda,
                     std::string selection_method);

  std::string_view Kind() const override { return "linear"; }
  const std::vector<std::string>& InputSensors() const override { return sensors_; }
  const std::vector<std::string>& Channels() const override { return channel_names_; }
  void Predict(const ThermalSample& sample, std::span<double> out_um) const override;
  nlohmann::json ToJson() const override;
  std::string Describe() const override;

  const std::vector<LinearChannel>& channel_models() const { return channels_; }
  double ridge_lambda() const { return ridge_lambda_; }

  static LinearThermalModel FromJson(const nlohmann::json& doc, const std::string& source, const std::string& path);

 private:
  std::vector<std::string> sensors_;
  std::vector<std::string> channel_names_;
  std::vector<LinearChannel> channels_;
  double ridge_lambda_ = 0;
  std::string selection_method_;
};

// Fits every error channel of a cleaned series (no NaN).
LinearThermalModel FitLinearModel(const ThermalSeries& series, const LinearFitOptions& options);

}  // namespace trueaxis::thermal
