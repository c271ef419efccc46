#include "trueaxis/thermal/linear_model.hpp"

#include <algorithm>

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "json_fields.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

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
    if (!c.count_cv.empty())
      out += fmt::format("  {} input(s) chosen by blocked 5-fold CV; RMS µm per count: {}\n", c.inputs.size(), c.count_cv);
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

// The smallest count whose CV RMSE is within this factor of the best is taken.
constexpr double kCountTolerance = 1.02;

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

// Blocked (contiguous-in-time) 5-fold CV RMS of one channel with `so`.
double BlockedCvRms(const Eigen::MatrixXd& temps, const Eigen::VectorXd& y, const SensorSelectionOptions& so,
                    double ridge_lambda) {
  const Eigen::Index n = temps.rows();
  constexpr int kFolds = 5;
  double ss = 0;
  Eigen::Index count = 0;
  for (int f = 0; f < kFolds; ++f) {
    const Eigen::Index lo = n * f / kFolds, hi = n * (f + 1) / kFolds;
    const Eigen::Index m = n - (hi - lo);
    if (m < 3 || hi <= lo) continue;
    Eigen::MatrixXd tt(m, temps.cols());
    Eigen::VectorXd yt(m);
    tt.topRows(lo) = temps.topRows(lo);
    tt.bottomRows(n - hi) = temps.bottomRows(n - hi);
    yt.head(lo) = y.head(lo);
    yt.tail(n - hi) = y.tail(n - hi);
    const ChannelSolution sol = SolveChannel(tt, yt, so, ridge_lambda);
    for (Eigen::Index r = lo; r < hi; ++r) {
      const double e = y(r) - sol.Predict(temps, r);
      ss += e * e;
      ++count;
    }
  }
  return count ? std::sqrt(ss / static_cast<double>(count)) : std::numeric_limits<double>::infinity();
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
  const int available = static_cast<int>(s.temperatures_c.cols());
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    const Eigen::VectorXd y = s.errors_um.col(c);
    SensorSelectionOptions chosen = o.selection;
    std::string count_cv;
    if (o.choose_count_by_cv && n >= 25) {
      // Candidate counts up to the bound, then every sensor; the smallest within 2 % of the best.
      std::vector<std::pair<SensorSelectionOptions, double>> tried;
      const int bound = std::min(o.selection.max_sensors, available);
      for (int m : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32}) {
        if (m > bound) break;
        SensorSelectionOptions so = o.selection;
        so.max_sensors = m;
        tried.emplace_back(so, BlockedCvRms(s.temperatures_c, y, so, o.ridge_lambda));
      }
      SensorSelectionOptions all = o.selection;
      all.method = SelectionMethod::kAll;
      all.max_sensors = available;
      tried.emplace_back(all, BlockedCvRms(s.temperatures_c, y, all, o.ridge_lambda));
      // The smallest count within 2 % of the best held-out RMSE, and never worse than all sensors
      // (the last candidate), so the default cannot lose to "all sensors" on the data it chose by.
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [so, rms] : tried) best = std::min(best, rms);
      const double limit = std::min(kCountTolerance * best, tried.back().second);
      for (const auto& [so, rms] : tried)
        if (rms <= limit) {
          chosen = so;
          break;
        }
      for (const auto& [so, rms] : tried)
        count_cv += fmt::format("{}{}: {:.3f}", count_cv.empty() ? "" : ", ",
                                so.method == SelectionMethod::kAll ? std::string("all") : std::to_string(so.max_sensors),
                                rms);
      selection = fmt::format("{}, sensor count by blocked 5-fold CV (per channel: sensor_count_cv_rms_um)",
                              SelectionMethodName(o.selection.method));
    }
    const ChannelSolution sol = SolveChannel(s.temperatures_c, y, chosen, o.ridge_lambda);
    LinearChannel ch;
    ch.name = s.error_names[static_cast<std::size_t>(c)];
    ch.intercept_um = sol.intercept_um;
    ch.count_cv = count_cv;
    for (std::size_t k = 0; k < sol.sensors.size(); ++k) {
      const std::string& sensor = s.temperature_names[static_cast<std::size_t>(sol.sensors[k])];
      int idx = -1;
      for (std::size_t u = 0; u < used.size(); ++u)
        if (used[u] == sensor) idx = static_cast<int>(u);
      if (idx < 0) {
        idx = static_cast<int>(used.size());
        used.push_back(sensor);
      }
      ch.inputs.push_back(idx);
      ch.k_um_per_c.push_back(sol.k_um_per_c[k]);
    }
    channels.push_back(std::move(ch));
  }
  return LinearThermalModel(std::move(used), std::move(channels), o.ridge_lambda, selection);
}

}  // namespace trueaxis::thermal
