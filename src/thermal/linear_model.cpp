#include "trueaxis/thermal/linear_model.hpp"

#include <algorithm>

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "json_fields.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/time_folds.hpp"

namespace trueaxis::thermal {

bool LinearFitOptions::IsValid(std::string* why) const {
  if (!(ridge_lambda >= 0) || !std::isfinite(ridge_lambda)) {
    if (why) *why = "ridge_lambda must be a finite number >= 0";
    return false;
  }
  return selection.IsValid(why);
}

LinearThermalModel::LinearThermalModel(std::vector<std::string> input_sensors, std::vector<LinearChannel> channels,
                                       double ridge_lambda, std::string selection_method)
    : sensors_(std::move(input_sensors)),
      channels_(std::move(channels)),
      ridge_lambda_(ridge_lambda),
      selection_method_(std::move(selection_method)) {
  for (const auto& c : channels_) channel_names_.push_back(c.name);
}

void LinearThermalModel::Predict(const ThermalSample& sample, std::span<double> out_um) const {
  for (std::size_t c = 0; c < channels_.size(); ++c) {
    const LinearChannel& ch = channels_[c];
    double e = ch.intercept_um;
    for (std::size_t k = 0; k < ch.inputs.size(); ++k)
      e += ch.k_um_per_c[k] * sample.temperatures_c[static_cast<std::size_t>(ch.inputs[k])];
    out_um[c] = e;
  }
}

nlohmann::json LinearThermalModel::ToJson() const {
  nlohmann::json channels = nlohmann::json::array();
  for (const auto& c : channels_) {
    std::vector<std::string> names;
    for (int i : c.inputs) names.push_back(sensors_[static_cast<std::size_t>(i)]);
    channels.push_back({{"name", c.name},
                        {"sensors", names},
                        {"k_um_per_c", c.k_um_per_c},
                        {"intercept_um", c.intercept_um}});
    if (!c.count_cv.empty()) channels.back()["sensor_count_cv_rms_um"] = c.count_cv;
    if (!c.cv_choice.empty()) channels.back()["cv_choice"] = c.cv_choice;
  }
  return {{"kind", "linear"},
          {"ridge_lambda", ridge_lambda_},
          {"selection", selection_method_},
          {"sensors", sensors_},
          {"channels", channels}};
}

std::string LinearThermalModel::Describe() const {
  std::string out;
  for (const auto& c : channels_) {
    out += fmt::format("{}: e_um = {}", c.name, FormatShortest(c.intercept_um));
    for (std::size_t k = 0; k < c.inputs.size(); ++k)
      out += fmt::format(" {:+.6g}*T[{}]", c.k_um_per_c[k], sensors_[static_cast<std::size_t>(c.inputs[k])]);
    out += '\n';
    if (c.IsConstant())
      out += fmt::format("  the constant (the training mean): no input beat it on time-ordered cross-validation{}; "
                         "held-out RMS µm (geometric mean over the folds): {}\n",
                         c.cv_choice.size() > 11 ? ": " + c.cv_choice.substr(10, c.cv_choice.size() - 11) : std::string(), c.count_cv);
    else if (!c.count_cv.empty())
      out += fmt::format("  {} input(s) ({}) chosen by time-ordered cross-validation; held-out RMS µm (geometric "
                         "mean over the folds): {}\n", c.inputs.size(), c.cv_choice, c.count_cv);
  }
  return out;
}

LinearThermalModel LinearThermalModel::FromJson(const nlohmann::json& doc, const std::string& source,
                                                const std::string& path) {
  detail::JsonFields f(source);
  const double lambda = f.Number(doc, path, "ridge_lambda");
  if (lambda < 0) f.Fail(f.Join(path, "ridge_lambda"), "must be >= 0");
  std::string selection = doc.contains("selection") ? f.String(doc, path, "selection") : "";
  std::vector<std::string> sensors = f.Strings(doc, path, "sensors");
  const auto& arr = f.Array(doc, path, "channels");
  std::vector<LinearChannel> channels;
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const std::string p = f.Index(f.Join(path, "channels"), i);
    LinearChannel ch;
    ch.name = f.String(arr[i], p, "name");
    std::vector<std::string> names = f.Strings(arr[i], p, "sensors");
    ch.k_um_per_c = f.Numbers(arr[i], p, "k_um_per_c");
    ch.intercept_um = f.Number(arr[i], p, "intercept_um");
    if (arr[i].contains("sensor_count_cv_rms_um")) ch.count_cv = f.String(arr[i], p, "sensor_count_cv_rms_um");
    if (arr[i].contains("cv_choice")) ch.cv_choice = f.String(arr[i], p, "cv_choice");
    if (names.size() != ch.k_um_per_c.size())
      f.Fail(f.Join(p, "k_um_per_c"), fmt::format("{} coefficients for {} sensors", ch.k_um_per_c.size(), names.size()));
    for (std::size_t k = 0; k < names.size(); ++k) {
      int idx = -1;
      for (std::size_t s = 0; s < sensors.size(); ++s)
        if (sensors[s] == names[k]) idx = static_cast<int>(s);
      if (idx < 0) f.Fail(f.Index(f.Join(p, "sensors"), k), "'" + names[k] + "' is not in the model's sensors list");
      if (std::find(ch.inputs.begin(), ch.inputs.end(), idx) != ch.inputs.end())
        f.Fail(f.Index(f.Join(p, "sensors"), k), "'" + names[k] + "' is listed twice");
      ch.inputs.push_back(idx);
    }
    channels.push_back(std::move(ch));
  }
  return LinearThermalModel(std::move(sensors), std::move(channels), lambda, std::move(selection));
}

namespace {

// The smallest count whose CV score is within this factor of the best is taken.
constexpr double kCountTolerance = 1.02;
// A fold RMS below this (µm) counts as this in the geometric mean (an exact fit scores finitely).
constexpr double kTinyRmsUm = 1e-9;

// One channel's least-squares (ridge) fit on the chosen sensors: intercept + k per sensor.
struct ChannelSolution {
  std::vector<int> sensors;
  double intercept_um = 0;
  std::vector<double> k_um_per_c;
  double Predict(const Eigen::MatrixXd& t, Eigen::Index r) const {
    double v = intercept_um;
    for (std::size_t j = 0; j < sensors.size(); ++j) v += k_um_per_c[j] * t(r, sensors[j]);
    return v;
  }
};

ChannelSolution SolveChannel(const Eigen::MatrixXd& temps, const Eigen::VectorXd& y, const SensorSelectionOptions& so,
                             double ridge_lambda) {
  const Eigen::Index n = temps.rows();
  SensorSelectionOptions sel_opt = so;
  sel_opt.max_sensors = std::max(1, std::min<int>(sel_opt.max_sensors, static_cast<int>(n) - 2));
  const SensorSelection sel = SelectSensors(temps, y, sel_opt);
  const auto p = static_cast<Eigen::Index>(sel.sensors.size());
  Eigen::MatrixXd x(n, p);
  for (Eigen::Index k = 0; k < p; ++k) x.col(k) = temps.col(sel.sensors[static_cast<std::size_t>(k)]);
  // Solve on centred, standardised columns (well-conditioned, lambda unit-free).
  const Eigen::RowVectorXd mean = x.colwise().mean();
  Eigen::MatrixXd z = x.rowwise() - mean;
  Eigen::VectorXd sd(p);
  for (Eigen::Index k = 0; k < p; ++k) {
    sd(k) = std::sqrt(z.col(k).squaredNorm() / static_cast<double>(n));
    if (sd(k) > 0) z.col(k) /= sd(k);
  }
  const double ymean = y.mean();
  const Eigen::VectorXd yc = y.array() - ymean;
  Eigen::MatrixXd a = z.transpose() * z;
  a.diagonal().array() += ridge_lambda * static_cast<double>(n);
  const Eigen::VectorXd b_std = a.completeOrthogonalDecomposition().solve(z.transpose() * yc);
  ChannelSolution out;
  out.sensors = sel.sensors;
  out.intercept_um = ymean;
  for (Eigen::Index k = 0; k < p; ++k) {
    const double k_raw = sd(k) > 0 ? b_std(k) / sd(k) : 0.0;
    out.k_um_per_c.push_back(k_raw);
    out.intercept_um -= k_raw * mean(k);
  }
  return out;
}

// Out-of-fold predictions of one channel over `folds` with `so` on the columns `cols` of `temps`
// (NaN on rows no fold validates); `cols` empty: the constant (each fold's training mean).
Eigen::VectorXd FoldPredictions(const Eigen::MatrixXd& temps, const Eigen::VectorXd& y, const TimeFolds& folds,
                                const std::vector<Eigen::Index>& cols, const SensorSelectionOptions& so,
                                double ridge_lambda) {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(y.size(), std::numeric_limits<double>::quiet_NaN());
  const Eigen::MatrixXd sub = cols.empty() ? Eigen::MatrixXd() : Eigen::MatrixXd(temps(Eigen::all, cols));
  for (const TimeFold& f : folds.folds) {
    const Eigen::VectorXd yt = y(f.train_rows);
    if (cols.empty()) {
      for (Eigen::Index r : f.validate_rows) out(r) = yt.mean();
      continue;
    }
    const ChannelSolution sol = SolveChannel(sub(f.train_rows, Eigen::all), yt, so, ridge_lambda);
    for (Eigen::Index r : f.validate_rows) out(r) = sol.Predict(sub, r);
  }
  return out;
}

// RMS of y − predicted over the rows with a prediction.
double HeldOutRms(const Eigen::VectorXd& y, const Eigen::VectorXd& predicted) {
  double ss = 0;
  Eigen::Index count = 0;
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (std::isfinite(predicted(r))) ss += (y(r) - predicted(r)) * (y(r) - predicted(r)), ++count;
  return count ? std::sqrt(ss / static_cast<double>(count)) : std::numeric_limits<double>::infinity();
}

// The factor a in [0, 1] of constant + a·(model − constant) with the least held-out RMS: how far
// the data supports moving from the constant toward the model.
double ShrinkTowardConstant(const Eigen::VectorXd& y, const Eigen::VectorXd& model, const Eigen::VectorXd& constant) {
  double num = 0, den = 0;
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (std::isfinite(model(r)) && std::isfinite(constant(r))) {
      const double d = model(r) - constant(r);
      num += (y(r) - constant(r)) * d;
      den += d * d;
    }
  return den > 0 ? std::clamp(num / den, 0.0, 1.0) : 1.0;
}

// The rows of `blocks`, in order.
std::vector<Eigen::Index> RowsOf(const std::vector<std::vector<Eigen::Index>>& blocks) {
  std::vector<Eigen::Index> out;
  for (const auto& b : blocks) out.insert(out.end(), b.begin(), b.end());
  return out;
}

// Whether `model` beats `constant` on the use-like blocks by more than one standard error: the
// per-block gains in mean squared residual (constant − model) are the replicates — neighbouring
// rows of a drift recording are not independent, blocks of them nearly are — and their mean must
// exceed its standard error (the one-standard-error rule, in favour of the simpler constant).
bool BeatsConstantBeyondNoise(const Eigen::VectorXd& y, const Eigen::VectorXd& model, const Eigen::VectorXd& constant,
                              const std::vector<std::vector<Eigen::Index>>& blocks) {
  std::vector<double> gain;
  for (const auto& b : blocks) {
    double g = 0;
    for (Eigen::Index r : b) g += std::pow(y(r) - constant(r), 2) - std::pow(y(r) - model(r), 2);
    gain.push_back(g / static_cast<double>(b.size()));
  }
  if (gain.size() < 2) return !gain.empty() && gain.front() > 0;
  const double k = static_cast<double>(gain.size());
  double mean = 0, var = 0;
  for (double g : gain) mean += g / k;
  for (double g : gain) var += (g - mean) * (g - mean) / (k - 1);
  return mean > std::sqrt(var / k);
}

// One candidate of the choice: the constant, or a count (or all) of an input set.
struct InputCandidate {
  std::string label;                // as printed: "constant", "3", "all", "all λ 0.1"
  std::string choice;               // as kept: "constant", "3 sensors", "all sensors and lags", ...
  std::vector<Eigen::Index> cols;   // the input set (columns of the series); empty: constant
  SensorSelectionOptions so;
  double ridge_lambda = 0;
  bool lags = false;                // the input set holds lagged inputs
  Eigen::VectorXd predicted;  // out of fold
  std::vector<double> fold_rms;  // held-out RMS per fold
  double score = 0;              // their geometric mean: what the candidates are ranked by
};

// The heavier ridge penalties offered on all inputs of a set, next to the one asked for (unit-free:
// the penalty acts on standardised temperatures). Many correlated inputs fitted with a light penalty
// follow the training rows closely and the future less well; a heavier one spreads the weight.
constexpr double kExtraRidgeLambdas[] = {1e-2, 1e-1};

// The candidates of one channel in order of growing complexity, with their fold RMS: the constant,
// counts of the plain sensors and all of them, then (with lagged inputs) counts of sensors and lags
// together and all inputs; all of a set also with the heavier ridge penalties.
std::vector<InputCandidate> CrossValidatedCandidates(const ThermalSeries& s, const Eigen::VectorXd& y,
                                                     const TimeFolds& folds, const LinearFitOptions& o) {
  std::vector<Eigen::Index> plain, every;
  for (std::size_t k = 0; k < s.temperature_names.size(); ++k) {
    every.push_back(static_cast<Eigen::Index>(k));
    if (!ParseLaggedName(s.temperature_names[k], nullptr, nullptr)) plain.push_back(static_cast<Eigen::Index>(k));
  }
  std::vector<InputCandidate> out;
  out.push_back({"constant", "constant", {}, o.selection, o.ridge_lambda, false, {}, {}, 0});
  auto add_set = [&](const std::vector<Eigen::Index>& cols, const std::string& what, bool lags) {
    const int available = static_cast<int>(cols.size());
    const int bound = std::min(o.selection.max_sensors, available);
    for (int m : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32}) {
      if (m > bound || m >= available) break;
      InputCandidate c{std::to_string(m), fmt::format("{} of the {}", m, what), cols, o.selection, o.ridge_lambda,
                       lags, {}, {}, 0};
      c.so.max_sensors = m;
      out.push_back(std::move(c));
    }
    InputCandidate all{"all", "all " + what, cols, o.selection, o.ridge_lambda, lags, {}, {}, 0};
    all.so.method = SelectionMethod::kAll;
    all.so.max_sensors = available;
    out.push_back(all);
    if (o.ridge_lambda > 0 && available > 1)
      for (double lambda : kExtraRidgeLambdas)
        if (lambda > o.ridge_lambda) {
          InputCandidate heavier = all;
          heavier.label = fmt::format("all λ {:g}", lambda);
          heavier.choice = fmt::format("all {}, ridge λ {:g}", what, lambda);
          heavier.ridge_lambda = lambda;
          out.push_back(std::move(heavier));
        }
  };
  if (!plain.empty()) add_set(plain, "sensors", false);
  if (every.size() > plain.size()) add_set(every, "sensors and lags", true);
  for (auto& c : out) {
    c.predicted = FoldPredictions(s.temperatures_c, y, folds, c.cols, c.so, c.ridge_lambda);
    double log_sum = 0;
    for (const TimeFold& f : folds.folds) {
      c.fold_rms.push_back(HeldOutRms(y(f.validate_rows), c.predicted(f.validate_rows)));
      log_sum += std::log(std::max(c.fold_rms.back(), kTinyRmsUm));
    }
    c.score = std::exp(log_sum / static_cast<double>(c.fold_rms.size()));
  }
  return out;
}

// Whether `other` scores as well as `anchor` within the folds' noise: the per-fold log ratios of
// their held-out RMS, log(other / anchor), have a mean within one standard error of 0 (or below it).
bool AsGoodWithinTheNoise(const InputCandidate& other, const InputCandidate& anchor) {
  const std::size_t k = anchor.fold_rms.size();
  if (k < 2 || other.fold_rms.size() != k) return false;
  std::vector<double> d;
  for (std::size_t f = 0; f < k; ++f)
    d.push_back(std::log(std::max(other.fold_rms[f], kTinyRmsUm)) - std::log(std::max(anchor.fold_rms[f], kTinyRmsUm)));
  double mean = 0, var = 0;
  for (double v : d) mean += v / static_cast<double>(k);
  for (double v : d) var += (v - mean) * (v - mean) / static_cast<double>(k - 1);
  return mean <= std::sqrt(var / static_cast<double>(k));
}

}  // namespace

LinearThermalModel FitLinearModel(const ThermalSeries& s, const LinearFitOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("linear fit options", why);
  const Eigen::Index n = s.Rows();
  if (n < 3) throw InputError(s.source, 0, "", fmt::format("{} row(s) to fit; need at least 3", n));
  if (s.temperatures_c.hasNaN() || s.errors_um.hasNaN())
    throw InputError(s.source, 0, "", "series holds missing values; clean it first (CleanSeries)");
  std::vector<std::string> used;  // union of selected sensors, in first-use order
  std::vector<LinearChannel> channels;
  std::string selection = SelectionMethodName(o.selection.method);
  const TimeFolds folds = o.choose_count_by_cv && n >= 25 ? MakeTimeFolds(s) : TimeFolds{};
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    const Eigen::VectorXd y = s.errors_um.col(c);
    // The fits averaged into the channel (one unless the choice averages several): input set
    // (empty: every column), selection and penalty.
    struct Member {
      std::vector<Eigen::Index> cols;
      SensorSelectionOptions so;
      double ridge_lambda = 0;
      double weight = 1;
    };
    std::vector<Member> members{{{}, o.selection, o.ridge_lambda, 1}};
    std::string count_cv, choice;
    bool constant = false;
    double shrink = 1;  // toward the constant: 1 = the model as fitted
    if (!folds.folds.empty()) {
      // Ranked by the geometric mean of the folds' held-out RMS (each fold counts by how much of
      // its error a candidate removes: one fold in a regime unlike the others — coolant switched on
      // for the first time — does not decide alone). Only candidates that are not worse than the
      // constant on the use-like rows (the latest fold; every experiment) nor on all folds together
      // are eligible, and of those the simplest within 2 % of the best (all inputs included) that
      // is not worse than the constant is taken, averaged with the eligible candidates of its kind
      // that score as well within the folds' noise. It is shrunk toward the constant as far as the
      // use-like rows ask, and kept only if it beats the constant there by more than the noise;
      // otherwise the channel is the constant.
      const std::vector<InputCandidate> tried = CrossValidatedCandidates(s, y, folds, o);
      const InputCandidate& mean = tried.front();
      const auto blocks = UseLikeBlocks(folds);
      const std::vector<Eigen::Index> use_rows = RowsOf(blocks);
      const double mean_use_rms = HeldOutRms(y(use_rows), mean.predicted(use_rows));
      const double mean_all_rms = HeldOutRms(y, mean.predicted);
      auto eligible_predictions = [&](const Eigen::VectorXd& p) {
        return HeldOutRms(y(use_rows), p(use_rows)) <= mean_use_rms && HeldOutRms(y, p) <= mean_all_rms;
      };
      auto eligible = [&](const InputCandidate& t) { return eligible_predictions(t.predicted); };
      double best = std::numeric_limits<double>::infinity();
      for (const auto& t : tried)
        if (eligible(t)) best = std::min(best, t.score);
      const double limit = std::min(kCountTolerance * best, mean.score);
      for (const auto& t : tried)
        if (eligible(t) && t.score <= limit) {
          choice = t.choice;
          constant = t.cols.empty();
          if (!constant) {
            members = {{t.cols, t.so, t.ridge_lambda, 1 / (t.score * t.score)}};
            Eigen::VectorXd predicted = t.predicted;
            // Averaged with every other eligible candidate of the same kind (plain sensors, or
            // sensors and lags) that is as good within the folds' noise: the choice among
            // near-equal input sets is itself noisy, and their average varies less than any of them.
            // Each counts by the inverse square of its score (forecasts combined by the inverse of
            // their mean squared error): the better of them weigh more.
            // Candidates that fit the same (a count above what the selection keeps) count once.
            std::vector<std::string> with;
            Eigen::VectorXd sum = members.front().weight * t.predicted;
            for (const auto& u : tried)
              if (&u != &t && !u.cols.empty() && u.lags == t.lags && eligible(u) && u.score <= mean.score &&
                  AsGoodWithinTheNoise(u, t) && u.fold_rms != t.fold_rms &&
                  std::none_of(tried.data(), &u, [&](const InputCandidate& v) { return v.fold_rms == u.fold_rms; })) {
                members.push_back({u.cols, u.so, u.ridge_lambda, 1 / (u.score * u.score)});
                sum += members.back().weight * u.predicted;
                with.push_back(u.choice);
              }
            double total = 0;
            for (const Member& m : members) total += m.weight;
            const Eigen::VectorXd average = sum / total;
            if (members.size() > 1 && eligible_predictions(average)) {
              predicted = average;
              choice += fmt::format(" averaged with {}", fmt::join(with, ", "));
            } else {
              members.resize(1);
            }
            // Shrunk toward the constant as far as the use-like rows ask (a ridge path's end point
            // is the constant; this is the step along it the latest data supports).
            shrink = ShrinkTowardConstant(y(use_rows), predicted(use_rows), mean.predicted(use_rows));
            const Eigen::VectorXd blended = mean.predicted + shrink * (predicted - mean.predicted);
            const double blended_use_rms = HeldOutRms(y(use_rows), blended(use_rows));
            if (shrink < 1) choice += fmt::format(", shrunk ×{:.2f} toward the constant", shrink);
            if (shrink == 0 || !BeatsConstantBeyondNoise(y, blended, mean.predicted, blocks)) {
              choice = fmt::format("constant ({}: did not beat it beyond the noise on the {}, RMS {:.3f} against "
                                   "{:.3f} µm)", choice, folds.by_experiment ? "experiments" : "latest fold",
                                   blended_use_rms, mean_use_rms);
              constant = true;
            } else {
              choice += fmt::format(" ({} RMS {:.3f} µm, the constant's {:.3f})",
                                    folds.by_experiment ? "experiments'" : "latest fold", blended_use_rms, mean_use_rms);
            }
          }
          break;
        }
      std::string set;
      for (const auto& t : tried) {
        const std::string group = t.cols.empty() ? "" : t.lags ? "with lags " : "sensors ";
        count_cv += fmt::format("{}{}{}: {:.3f}", count_cv.empty() ? "" : group != set ? "; " : ", ",
                                group != set ? group : "", t.label, t.score);
        set = group;
      }
      selection = fmt::format("{}, inputs by {} CV (per channel: cv_choice, sensor_count_cv_rms_um)",
                              SelectionMethodName(o.selection.method), folds.Name());
    }
    LinearChannel ch;
    ch.name = s.error_names[static_cast<std::size_t>(c)];
    ch.count_cv = count_cv;
    ch.cv_choice = choice;
    if (constant) {  // the training mean: no input earned its place
      ch.intercept_um = y.mean();
      channels.push_back(std::move(ch));
      continue;
    }
    // The members' fits on all the rows, averaged with their weights coefficient by coefficient
    // (the average of linear models is linear), then shrunk toward the training mean.
    double total_weight = 0;
    for (const Member& m : members) total_weight += m.weight;
    double intercept_um = 0;
    std::vector<std::pair<int, double>> k_by_column;  // column of the series, k
    for (const Member& m : members) {
      ChannelSolution sol;
      if (m.cols.empty()) {
        sol = SolveChannel(s.temperatures_c, y, m.so, m.ridge_lambda);
      } else {
        sol = SolveChannel(s.temperatures_c(Eigen::all, m.cols), y, m.so, m.ridge_lambda);
        for (int& k : sol.sensors) k = static_cast<int>(m.cols[static_cast<std::size_t>(k)]);
      }
      const double weight = m.weight / total_weight;
      intercept_um += weight * sol.intercept_um;
      for (std::size_t k = 0; k < sol.sensors.size(); ++k) {
        auto at = std::find_if(k_by_column.begin(), k_by_column.end(),
                               [&](const auto& e) { return e.first == sol.sensors[k]; });
        if (at == k_by_column.end()) at = k_by_column.insert(k_by_column.end(), {sol.sensors[k], 0.0});
        at->second += weight * sol.k_um_per_c[k];
      }
    }
    ch.intercept_um = shrink * intercept_um + (1 - shrink) * y.mean();
    for (const auto& [column, k_um_per_c] : k_by_column) {
      const std::string& sensor = s.temperature_names[static_cast<std::size_t>(column)];
      int idx = -1;
      for (std::size_t u = 0; u < used.size(); ++u)
        if (used[u] == sensor) idx = static_cast<int>(u);
      if (idx < 0) {
        idx = static_cast<int>(used.size());
        used.push_back(sensor);
      }
      ch.inputs.push_back(idx);
      ch.k_um_per_c.push_back(shrink * k_um_per_c);
    }
    channels.push_back(std::move(ch));
  }
  return LinearThermalModel(std::move(used), std::move(channels), o.ridge_lambda, selection);
}

}  // namespace trueaxis::thermal
