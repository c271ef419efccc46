#pragma once
// Cross-validation folds that look like the use a thermal model is judged by: predicting a later
// stretch of the machine's life from what came before (docs/thermal-models.md "How many inputs,
// and which"). A drift recording is a time series — neighbouring rows are not independent and the
// start (a warm-up) differs from the long steady part that follows — so folds are not drawn at
// random nor cut evenly through the recording:
// - several experiments (recordings) in the rows: one fold per experiment, validated by a fit on
//   the others (leave one experiment out);
// - one recording: forward chaining over its second half: kForwardFolds validation blocks of
//   equal length cover the last half of the rows, each validated by a fit on every row before it.
//   The warm-up at the start is always trained on and never what is judged.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

inline constexpr int kForwardFolds = 5;

struct TimeFold {
  std::vector<Eigen::Index> train_rows, validate_rows;  // row indices into the series, ascending
};

struct TimeFolds {
  std::vector<TimeFold> folds;
  bool by_experiment = false;
  // "forward-chaining 5-fold" or "leave-one-experiment-out 3-fold", for what is printed.
  std::string Name() const;
};

// The folds of `series` (ThermalSeries::experiment decides, whatever experiment_names holds).
// Folds with fewer than 3 training or no validation rows are left out.
TimeFolds MakeTimeFolds(const ThermalSeries& series);

// The validated rows that look most like the use, as consecutive blocks that serve as replicates
// when a model is compared with the constant on them: forward chaining — the last fold (the latest
// stretch, predicted from everything before it, like the rows after the training) cut into
// kForwardFolds blocks of equal length; leave one experiment out — every fold's rows (a new
// experiment is the use, and each is one). Empty when there are no folds.
std::vector<std::vector<Eigen::Index>> UseLikeBlocks(const TimeFolds& folds);

}  // namespace trueaxis::thermal
