#pragma once
// Tool tip thermal error from Tv (docs/tool-thermal.md, "Models"), per tool.
// Every model predicts the Z error at the tip in µm (error, not correction:
// docs/sign-convention.md) from the course of Tv while the tool is mounted:
//
//   one        e = a + b·(Tv − T_std)                       one curve for all intervals
//   intervals  e = a_k + b_k·(Tv − T_std) + c_k·(Tv − Tv_k0), k = WT1/WT2/WT3
//              seed 001: a sub-model per interval; Tv_k0 = the (smoothed) Tv when the
//              current interval began, so a cooling branch starts from where heating ended
//              (start-up and an interval with too few training rows: the one model;
//              an interval spanning under half the training Tv range: the one model's
//              slope b; c_k for heating and cooling only, where the rise is not Tv again,
//              |corr| < 0.95). Outside the interval's own training ranges of Tv and of the
//              rise the sub-model's difference from the one model is held at the edge, never
//              extrapolated. That difference is applied with a weight w ∈ [0, 1]: the blend
//              that best predicted the held-out quarters of `best`'s cross-validation; w = 0
//              falls back to the one curve (fitted = false).
//   lag        e = a + b·(L − T_std), dL/dt = (Tv − L)/τ     a first-order lag of Tv
//   two_body   e = a + b·(Tv − T_std) + c·(L − T_std)        ours: the surface (fast) and
//              a lagged body (slow); the hysteresis of two bodies is exactly this shape
//   zones      e = a + Σ b_r·(Tr − T_std)                   ours: the zone means themselves
//              (Tv's area weights are not the growth's: a hot tip on a thin tool weighs
//              little in Tv but grows a lot; needs the zone means, ridge λ = 1e-4·mean diag).
//              Given the free growth per zone (ZoneGrowthUmPerC of the tool file), each Tr
//              beyond the range it was trained on adds −growth_r per °C past the edge (the
//              fit is not extrapolated: a narrow training range fixes no slope), and with
//              under 5 rows per coefficient the slopes are −growth_r, the intercept fitted
//   best       zones when the training rows carry zone means (the growth is linear in the
//              bodies' temperatures, which they sample); else the one of {one, intervals, lag,
//              two_body} with the lowest error in a four-fold blocked cross-validation of the
//              training data (each contiguous quarter predicted by the models fitted on the rest)
//
// L restarts at Tv when a tool is mounted. τ is chosen by least squares over a
// geometric grid (5 s … 2 h); the classifier's window and dead band from the
// data (interval_classifier.hpp) by the training fit of the interval model.
// Pure: rows in, model out; JSON to store it with the tool.
#include <array>
#include <limits>
#include <optional>
#include <utility>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trueaxis/tooltherm/interval_classifier.hpp"

namespace trueaxis::tooltherm {

enum class ToolModelKind { kNone = 0, kOne, kIntervals, kLag, kTwoBody, kZones, kBest };
inline constexpr std::array<ToolModelKind, 7> kToolModelKinds = {
    ToolModelKind::kNone,    ToolModelKind::kOne,   ToolModelKind::kIntervals, ToolModelKind::kLag,
    ToolModelKind::kTwoBody, ToolModelKind::kZones, ToolModelKind::kBest};
const char* ToolModelKindName(ToolModelKind k);
ToolModelKind ParseToolModelKind(const std::string& name);  // std::invalid_argument when unknown

struct ToolRecord {
  double time_s = 0;
  double tv_c = 0;
  double error_um = 0;   // true tip error (training) — ignored by prediction
  bool restart = false;  // first sample after the tool was mounted
  std::vector<double> zone_c;  // Tr per zone (optional; the zones model needs it)
};

// The rows as columns (what the classifier and the fits take).
struct ToolColumns {
  std::vector<double> time_s, tv_c, error_um;
  std::vector<bool> restart;
};
ToolColumns ColumnsOf(const std::vector<ToolRecord>& rows);

struct LinearTerm {
  double intercept_um = 0;
  double per_c_um = 0;  // µm per °C of (T − T_std)
};

// Seed 001's sub-model of one interval: e = a_k + b_k·(Tv − T_std) + c_k·(Tv − Tv_k0), applied as
// the one model plus weight × its difference, the difference evaluated with Tv and the rise
// clamped to the ranges the interval was trained on.
struct IntervalTerm {
  LinearTerm line;                 // a_k, b_k
  double per_c_since_start_um = 0; // c_k, µm per °C of rise since the interval began
  double tv_from_c = -1e9, tv_to_c = 1e9;      // training range of Tv
  double rise_from_c = 0, rise_to_c = 0;       // training range of Tv − Tv_k0
  // Held-out evidence (the four-fold blocked cross-validation of `best`): RMS over the held-out
  // rows the fold models put in this interval, of this sub-model and of the one model there.
  int cv_rows = 0;
  double cv_rms_um = 0, cv_one_rms_um = 0;
  double weight = 1;  // share of the difference from the one model that is applied (held-out blend)
};

struct ToolErrorModel {
  int tool = 0;
  double standard_temp_c = 20;
  LinearTerm one;
  std::array<IntervalTerm, 3> interval{};
  std::array<bool, 3> interval_fitted{};
  std::array<int, 3> interval_rows{};
  ToolClassifierOptions classifier;
  double lag_tau_s = 600;
  LinearTerm lag;
  double two_body_tau_s = 600;
  double two_body_intercept_um = 0, two_body_tv_um_per_c = 0, two_body_lag_um_per_c = 0;
  double zone_intercept_um = 0;
  std::vector<double> zone_um_per_c;          // empty: no zones model (no zone means in training)
  // Beyond the zone means the tool was trained on, the free growth of the gauge length (docs/tool-thermal.md,
  // "Beyond the training range"): per zone the training range of Tr (°C) and the slope that continues
  // the fit past it (−free growth of the zone's part of the axis, µm/°C). Empty: the fit extrapolates.
  std::vector<std::pair<double, double>> zone_training_range_c;
  std::vector<double> zone_beyond_um_per_c;
  ToolModelKind best = ToolModelKind::kOne;          // see `best` above
  ToolModelKind best_without_zones = ToolModelKind::kOne;  // the cross-validation's choice of the Tv models
  std::array<double, kToolModelKinds.size()> cv_rms_um{};          // by ToolModelKind (0 where not evaluated)
  SeriesStatistics training;  // sample interval and Tv noise of the training data
  int training_rows = 0;
  // The lowest and highest Tv of the training data (JSON training.tv_range_c; NaN in files written
  // before it was stored).
  double training_tv_from_c = std::numeric_limits<double>::quiet_NaN();
  double training_tv_to_c = std::numeric_limits<double>::quiet_NaN();

  // Not empty: this tool had too little training and the model was built from these tools'
  // models (tool_fallback.hpp); a stand-in, flagged wherever it is used.
  std::vector<int> fallback_from_tools;

  // The Tv range the model was trained on (°C): training_tv_from/to_c, else (older files) the
  // union of its fitted intervals' ranges; nullopt when neither is known.
  std::optional<std::pair<double, double>> TrainingTvRangeC() const;

  nlohmann::json ToJson() const;
  nlohmann::json ZonesJson() const;  // the "zones" object of ToJson
  static ToolErrorModel FromJson(const nlohmann::json& j, const std::string& source);
};

// Causal prediction, one sample at a time (what a runtime does).
class ToolErrorPredictor {
 public:
  ToolErrorPredictor(const ToolErrorModel& model, ToolModelKind kind);
  // restart: the tool was just mounted (classifier and lag start anew). zone_c: Tr per zone;
  // the zones model without them (or of another count) predicts with the one model.
  double Push(double time_s, double tv_c, bool restart, std::span<const double> zone_c = {});
  ThermalInterval interval() const { return interval_; }
  // Tv − Tv_k0: the rise of Tv since the current interval began (Tv_k0 = Tv smoothed over half
  // the classifier's window when the class changed; 0 right after a mounting).
  double rise_c() const { return rise_c_; }

 private:
  const ToolErrorModel* m_;
  ToolModelKind kind_;
  DwellIntervalClassifier classifier_;
  ThermalInterval interval_ = ThermalInterval::kStartUp;
  double lag_c_ = 0, two_body_lag_c_ = 0, last_t_ = 0;
  double smooth_tv_c_ = 0, interval_start_tv_c_ = 0, rise_c_ = 0;  // Tv_k0 of the current interval
};

std::vector<double> PredictSeries(const ToolErrorModel& model, ToolModelKind kind, const std::vector<ToolRecord>& rows);

// The zones model fits its own slopes from this many rows per coefficient (zones + 1) on.
inline constexpr std::size_t kMinZoneRowsPerCoefficient = 5;

// Needs ≥ 20 rows, the first a restart, time increasing within each mounting
// (std::invalid_argument otherwise). `warnings` gets intervals left to the one model.
// zone_growth_um_per_c: the free growth per zone (µm/°C, ZoneGrowthUmPerC); empty: the zones
// model is the fit alone.
ToolErrorModel FitToolErrorModel(int tool, const std::vector<ToolRecord>& rows, double standard_temp_c,
                                 std::vector<std::string>* warnings = nullptr,
                                 std::span<const double> zone_growth_um_per_c = {});

}  // namespace trueaxis::tooltherm
