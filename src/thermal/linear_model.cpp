#include "trueaxis/thermal/linear_model.hpp"

#include <cmath>

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
    if (names.size() != ch.k_um_per_c.size())
      f.Fail(f.Join(p, "k_um_per_c"), fmt::format("{} coefficients for {} sensors", ch.k_um_per_c.size(), names.size()));
    for (std::size_t k = 0; k < names.size(); ++k) {
      int idx = -1;
      for (std::size_t s = 0; s < sensors.size(); ++s)
        if (sensors[s] == names[k]) idx = static_cast<int>(s);
      if (idx < 0) f.Fail(f.Index(f.Join(p, "sensors"), k), "'" + names[k] + "' is not in the model's sensors list");
      ch.inputs.push_back(idx);
    }
    channels.push_back(std::move(ch));
  }
  return LinearThermalModel(std::move(sensors), std::move(channels), lambda, std::move(selection));
}

LinearThermalModel FitLinearModel(const ThermalSeries& s, const LinearFitOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("linear fit options", why);
  const Eigen::Index n = s.Rows();
  if (n < 3) throw InputError(s.source, 0, "", fmt::format("{} row(s) to fit; need at least 3", n));
  if (s.temperatures_c.hasNaN() || s.errors_um.hasNaN())
    throw InputError(s.source, 0, "", "series holds missing values; clean it first (CleanSeries)");
  std::vector<std::string> used;  // union of selected sensors, in first-use order
  std::vector<LinearChannel> channels;
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    const Eigen::VectorXd y = s.errors_um.col(c);
    SensorSelectionOptions sel_opt = o.selection;
    sel_opt.max_sensors = std::min<int>(sel_opt.max_sensors, static_cast<int>(n) - 2);
    if (sel_opt.max_sensors < 1) sel_opt.max_sensors = 1;
    SensorSelection sel = SelectSensors(s.temperatures_c, y, sel_opt);
    const auto p = static_cast<Eigen::Index>(sel.sensors.size());
    Eigen::MatrixXd x(n, p);
    for (Eigen::Index k = 0; k < p; ++k) x.col(k) = s.temperatures_c.col(sel.sensors[static_cast<std::size_t>(k)]);
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
    a.diagonal().array() += o.ridge_lambda * static_cast<double>(n);
    Eigen::VectorXd b_std = a.completeOrthogonalDecomposition().solve(z.transpose() * yc);
    LinearChannel ch;
    ch.name = s.error_names[static_cast<std::size_t>(c)];
    ch.intercept_um = ymean;
    for (Eigen::Index k = 0; k < p; ++k) {
      const double k_raw = sd(k) > 0 ? b_std(k) / sd(k) : 0.0;
      const std::string& sensor = s.temperature_names[static_cast<std::size_t>(sel.sensors[static_cast<std::size_t>(k)])];
      int idx = -1;
      for (std::size_t u = 0; u < used.size(); ++u)
        if (used[u] == sensor) idx = static_cast<int>(u);
      if (idx < 0) {
        idx = static_cast<int>(used.size());
        used.push_back(sensor);
      }
      ch.inputs.push_back(idx);
      ch.k_um_per_c.push_back(k_raw);
      ch.intercept_um -= k_raw * mean(k);
    }
    channels.push_back(std::move(ch));
  }
  return LinearThermalModel(std::move(used), std::move(channels), o.ridge_lambda,
                            SelectionMethodName(o.selection.method));
}

}  // namespace trueaxis::thermal
