#pragma once
// Lagged temperatures as model inputs. A structure's thermal error follows its own temperature
// field, which lags what a surface sensor reads (a spindle's growth lags its housing sensor, a
// screw lags its nut): a first-order lag of a sensor, L' = (T − L)/τ, is often a better input than
// the reading itself. Each sensor is offered at several time constants as extra input columns named
// "<sensor>@lag<τ>s" (e.g. "t4@lag1800s"); the models' sensor selection (and its cross-validated
// count) chooses among raw and lagged inputs like among any sensors, so the data decides which lags
// matter. The lag is causal, so a runtime computes the same inputs sample by sample
// (`InputLagFilter`); it starts at the first reading (a cold start is at rest) and restarts at a
// new experiment or after a gap longer than kLagResetGapFactor sample steps.
#include <string>
#include <vector>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

inline constexpr double kLagResetGapFactor = 10.0;

// Machine-tool structures have thermal time constants from minutes to hours; the default grid
// covers 10 min … 4.5 h in factors of 3 (only those up to a third of the longest experiment are used).
std::vector<double> DefaultLagGridS();

std::string LaggedName(const std::string& sensor, double tau_s);
// true and the parts when `name` is a lagged input's name.
bool ParseLaggedName(const std::string& name, std::string* sensor, double* tau_s);

// The rows whose lagged inputs have not yet forgotten where they started: within kLagSettleTaus ×
// the longest τ among `inputs` of the series' start, of each experiment's start or of a lag reset
// after a gap. There a lag assumes the machine was at rest before (a cold start); on a file cut
// out of a longer recording the prediction differs from that of the whole recording.
inline constexpr double kLagSettleTaus = 3.0;  // e^-3: 5 % of the start value left
struct LagStartUp {
  double longest_tau_s = 0;  // 0: no lagged input
  double settle_s = 0;       // kLagSettleTaus × longest_tau_s
  Eigen::Index rows = 0;     // rows within settle_s of a start
  int starts = 0;            // lag starts (series start, experiments, resets)
};
LagStartUp LagStartUpRows(const ThermalSeries& series, const std::vector<std::string>& inputs);

// The series with, for every raw sensor and every τ in `taus_s` (τ ≤ a third of the longest
// experiment's duration; others are skipped and listed in `skipped`), a lagged column appended.
ThermalSeries AddLaggedTemperatures(const ThermalSeries& series, const std::vector<double>& taus_s,
                                    std::vector<double>* skipped = nullptr);

// The series with the lagged columns among `needed` that it lacks computed from their sensors
// (InputError naming the sensor when the base sensor is missing). Used by PredictSeries so a model
// fitted on lagged inputs predicts from a plain recording.
ThermalSeries WithLaggedInputs(const ThermalSeries& series, const std::vector<std::string>& needed);

// One lagged input, sample by sample, for a runtime. Allocation-free after construction.
class InputLagFilter {
 public:
  explicit InputLagFilter(double tau_s) : tau_s_(tau_s) {}
  // Returns the lagged value at time_s; the first sample (or one after a reset) starts the lag at
  // the reading itself.
  double Push(double time_s, double reading_c);
  void Reset() { started_ = false; }

 private:
  double tau_s_;
  bool started_ = false;
  double last_time_s_ = 0, value_c_ = 0;
};

}  // namespace trueaxis::thermal
