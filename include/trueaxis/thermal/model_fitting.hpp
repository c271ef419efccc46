#pragma once
// One entry point to fit any thermal model kind by name, and the
// train/validate evaluation run behind `trueaxis thermal evaluate`
// (docs/thermal-models.md).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/thermal/evaluation.hpp"
#include "trueaxis/thermal/hysteresis_model.hpp"
#include "trueaxis/thermal/linear_model.hpp"
#include "trueaxis/thermal/pso_bp_network.hpp"
#include "trueaxis/thermal/series_cleaning.hpp"

namespace trueaxis::thermal {

// mlr: least squares on selected sensors; ridge: ridge_lambda > 0 on the same;
// pso-bp: seed 003 network; hysteresis: seed 001 per-interval ridge models;
// auto: mlr, ridge or hysteresis, whichever has the lowest time-ordered cross-validated RMSE on
// the rows it is given (time_folds.hpp), refitted on all of them (pso-bp is left out of
// the choice: it costs seconds per fit and never won on our recordings).
enum class ModelKind { kMlr, kRidge, kPsoBp, kHysteresis, kAuto };
const char* ModelKindName(ModelKind k);
bool ParseModelKind(const std::string& text, ModelKind* out);

struct ThermalFitOptions {
  ModelKind kind = ModelKind::kRidge;
  LinearFitOptions linear;        // mlr/ridge (mlr forces ridge_lambda = 0)
  double ridge_lambda = 1e-3;     // used by ridge and by the hysteresis sub-models
  PsoBpOptions network;
  HysteresisFitOptions hysteresis;  // its sub_model is taken from `linear` + ridge_lambda
  bool sensors_listed = false;      // the user named the inputs (--sensors-list): labelled so, not "all sensors"

  bool IsValid(std::string* why) const;
};

// Fits a cleaned series. `fit_report` (optional) receives a short text of
// what training did (PSO/BP errors for the network).
std::unique_ptr<ThermalErrorModel> FitThermalModel(const ThermalSeries& series, const ThermalFitOptions& options,
                                                   std::string* fit_report = nullptr);

struct ModelEvaluation {
  std::string name;
  std::unique_ptr<ThermalErrorModel> model;
  Eigen::MatrixXd predicted_um;  // every row of the series
  std::vector<ChannelMetrics> train, validate;
  double fit_seconds = 0;
  std::string fit_report;
};

// One train/validate split. A leave-one-experiment-out evaluation has one fold per experiment.
struct SplitFold {
  std::string name;  // e.g. "experiment 2 (b.csv)"
  std::vector<Eigen::Index> train_rows, validate_rows;
};

struct ThermalEvaluation {
  ThermalSeries series;  // cleaned
  SeriesCleaningReport cleaning;
  std::vector<SpeedBlock> blocks;
  std::vector<int> train_blocks, validate_blocks;
  // Single split: the rows of its one fold. Several folds (leave-one-experiment-out): every row is
  // validated by the fold that held it out (validate_rows = all rows), and the training metrics are
  // those of the model fitted on all rows (the model shown).
  std::vector<Eigen::Index> train_rows, validate_rows;
  std::vector<SplitFold> folds;
  std::string split;       // how the split was made, in words
  bool in_sample = false;  // validation rows overlap training rows
  double time_split_fraction = 0;  // > 0: split in time (last fraction validated), blocks unused
  std::vector<ChannelMetrics> baseline_train, baseline_validate;
  // The trivial model every real one must beat: a constant per channel equal to the training
  // mean of the error (an offset is most of the error when it starts at zero).
  std::vector<ChannelMetrics> constant_train, constant_validate;
  std::vector<ModelEvaluation> models;

  std::string SplitDescription() const;
  std::string BriefReport() const;   // metrics table as text
  std::string MarkdownTable() const;  // validation (and training) metrics per channel and model
};

struct EvaluationOptions {
  std::vector<ThermalFitOptions> models;
  std::string train_blocks = "auto";     // "auto": the first 60 % of blocks (rounded up); "all"; or "0-8"
  std::string validate_blocks = "auto";  // "auto": the blocks not trained on (all when one block)
  // > 0: a split in time instead of by blocks: train on the first (1 − f) of the rows, validate on
  // the last f. With both block options "auto" and a single speed block (no spindle column, or a
  // constant speed) the split is in time with f = 0.3 — never silently in-sample.
  double validate_last_fraction = 0;
  // Other splits (each replaces the block options; at most one may be given):
  std::string validate_rows;         // "A-B[,C-D]": validate these data rows (0-based), train on the rows before
  std::string validate_hours;        // "A-B": validate the rows whose time_s lies in [A, B] hours (same)
  bool train_after_validation = false;  // rows/hours splits: also train on the rows after the validated ones
  std::string validate_experiments;  // "1,3" (0-based) or "each" (leave-one-experiment-out); a
                                     // series of several experiments defaults to "each"
  // Adds ridge on all sensors to the models (unless one is asked for): the reference a sensor
  // selection must beat.
  bool all_sensors_reference = true;
  // Told before each model fit (`done` of `total`, and which), e.g. for a progress line. Empty: nothing.
  std::function<void(std::size_t done, std::size_t total, const std::string& what)> progress;
};

ThermalEvaluation EvaluateThermalModels(const ThermalSeries& cleaned, SeriesCleaningReport cleaning,
                                        const EvaluationOptions& options);

// Self-contained HTML: split, metrics, measured vs predicted over time,
// residuals, chosen sensors, per model and channel.
void WriteThermalReport(const ThermalEvaluation& evaluation, const std::string& path);

}  // namespace trueaxis::thermal
