// Seed 004 tracking-error model: derivatives, prediction, feed-forward choice, JSON.
#include "trueaxis/fiveaxis/tracking_model.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::fiveaxis {

ModelCoefficients AxisErrorModel::At(double kf) const {
  ModelCoefficients c;
  for (int i = 0; i < kModelTerms; ++i) c[i] = without_ff[i] + kf * (full_ff[i] - without_ff[i]);
  return c;
}

int HalfWindowSamples(double window_s, double dt_s) { return std::max(2, static_cast<int>(std::lround(window_s / dt_s / 2))); }

Derivatives SavitzkyGolay(const std::vector<double>& x, double dt_s, int m) {
  // Least-squares cubic over t = −m..m: rows of the pseudo-inverse give the
  // derivatives at the centre.
  Eigen::MatrixXd vander(2 * m + 1, 4);
  for (int i = -m; i <= m; ++i)
    for (int p = 0; p < 4; ++p) vander(i + m, p) = std::pow(static_cast<double>(i), p);
  const Eigen::MatrixXd pinv = (vander.transpose() * vander).ldlt().solve(vander.transpose());
  const std::size_t n = x.size();
  Derivatives d;
  d.v.assign(n, 0.0);
  d.a.assign(n, 0.0);
  d.j.assign(n, 0.0);
  if (n == 0) return d;
  for (std::size_t k = 0; k < n; ++k) {
    double c1 = 0, c2 = 0, c3 = 0;
    for (int i = -m; i <= m; ++i) {
      const long idx = std::clamp<long>(static_cast<long>(k) + i, 0, static_cast<long>(n) - 1);
      c1 += pinv(1, i + m) * x[idx];
      c2 += pinv(2, i + m) * x[idx];
      c3 += pinv(3, i + m) * x[idx];
    }
    d.v[k] = c1 / dt_s;
    d.a[k] = 2 * c2 / (dt_s * dt_s);
    d.j[k] = 6 * c3 / (dt_s * dt_s * dt_s);
  }
  return d;
}

namespace {

// Outputs of `count` discrete Laguerre filters (pole exp(−dt/τ)) driven by x:
// an orthonormal basis of stable impulse responses — lags and ringing alike.
void LaguerreBank(const std::vector<double>& x, double dt_s, std::vector<double>* out, int count) {
  const double p = std::exp(-dt_s / kLaguerreTimeConstantS), gain = std::sqrt(1 - p * p);
  const std::size_t n = x.size();
  std::vector<double> in(n);
  for (int k = 0; k < count; ++k) {
    std::vector<double>& y = out[k];
    y.assign(n, 0.0);
    double prev_y = 0, prev_in = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (k == 0) y[i] = prev_y = p * prev_y + gain * x[i];
      else {
        y[i] = prev_y = p * prev_y + prev_in - p * in[i];
        prev_in = in[i];
      }
    }
    in = y;
  }
}

}  // namespace

std::array<std::vector<double>, kModelTerms> ModelRegressors(const std::vector<double>& command, double dt_s,
                                                             double derivative_window_s, double friction_band,
                                                             const std::vector<double>* direction_from) {
  const int half_window = HalfWindowSamples(derivative_window_s, dt_s);
  Derivatives d = SavitzkyGolay(command, dt_s, half_window);
  const std::vector<double> direction_v = direction_from ? SavitzkyGolay(*direction_from, dt_s, half_window).v : d.v;
  std::array<std::vector<double>, kModelTerms> r;
  const std::size_t n = command.size();
  // Direction of motion, turning over within the friction band.
  std::vector<double> sign(n);
  for (std::size_t i = 0; i < n; ++i) sign[i] = std::tanh(direction_v[i] / friction_band);
  LaguerreBank(d.a, dt_s, &r[kSeedTerms], kLagTerms);
  LaguerreBank(sign, dt_s, &r[kSeedTerms + kLagTerms], kFrictionTerms);
  r[0] = std::move(d.v);
  r[1] = std::move(d.a);
  r[2] = std::move(d.j);
  return r;
}

namespace {

std::vector<double> Column(const std::vector<AxisVector>& q, int axis) {
  std::vector<double> c(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) c[i] = q[i][axis];
  return c;
}

int UsedTerms(const TrackingErrorModel& model) { return model.with_extensions ? kModelTerms : kSeedTerms; }

}  // namespace

std::vector<AxisVector> PredictTrackingError(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                             double dt_s, double kf, const std::vector<AxisVector>* direction_from) {
  std::vector<AxisVector> e(command.size(), AxisVector{});
  for (int a = 0; a < kAxisCount; ++a) {
    const std::vector<double> direction = direction_from ? Column(*direction_from, a) : std::vector<double>{};
    const auto r = ModelRegressors(Column(command, a), dt_s, model.derivative_window_s, model.axes[a].friction_band,
                                   direction_from ? &direction : nullptr);
    const auto c = model.axes[a].At(kf);
    for (int t = 0; t < UsedTerms(model); ++t)
      for (std::size_t i = 0; i < command.size(); ++i) e[i][a] += c[t] * r[t][i];
  }
  return e;
}

FeedForwardChoice ChooseFeedForward(const TrackingErrorModel& model, const std::vector<AxisVector>& command, double dt_s) {
  FeedForwardChoice choice;
  double sum = 0;
  int count = 0;
  for (int a = 0; a < kAxisCount; ++a) {
    const auto r = ModelRegressors(Column(command, a), dt_s, model.derivative_window_s, model.axes[a].friction_band);
    const auto& ax = model.axes[a];
    double num = 0, den = 0;
    for (std::size_t i = 0; i < command.size(); ++i) {
      double e0 = 0, e1 = 0;
      for (int t = 0; t < UsedTerms(model); ++t) {
        e0 += ax.without_ff[t] * r[t][i];
        e1 += ax.full_ff[t] * r[t][i];
      }
      num += e0 * (e1 - e0);
      den += (e1 - e0) * (e1 - e0);
    }
    choice.per_axis[a] = std::numeric_limits<double>::quiet_NaN();
    if (den <= 1e-30) continue;  // axis does not move
    choice.per_axis[a] = -num / den;
    sum += choice.per_axis[a];
    ++count;
  }
  choice.averaged = count > 0 ? sum / count : 0.0;
  return choice;
}

std::string ModelToJson(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names) {
  nlohmann::ordered_json j;
  j["format"] = "trueaxis five-axis tracking-error model (seed 004)";
  j["derivative_window_s"] = model.derivative_window_s;
  j["with_extensions"] = model.with_extensions;
  j["terms"] = "v, a, j, 10 Laguerre filters of a, 8 of tanh(v / friction_band), pole 10 ms";
  for (int a = 0; a < kAxisCount; ++a) {
    const auto& ax = model.axes[a];
    j["axes"].push_back({{"axis", names[a]}, {"without_ff", ax.without_ff}, {"full_ff", ax.full_ff},
                         {"friction_band", ax.friction_band}, {"fit_rms", ax.fit_rms}, {"test_rms", ax.signal_rms}});
  }
  return j.dump(2) + "\n";
}

TrackingErrorModel ModelFromJson(const std::string& text, const std::string& source) {
  TrackingErrorModel model;
  try {
    const auto j = nlohmann::json::parse(text);
    model.derivative_window_s = j.at("derivative_window_s").get<double>();
    model.with_extensions = j.value("with_extensions", true);
    const auto& axes = j.at("axes");
    if (!axes.is_array() || axes.size() != kAxisCount) throw InputError(source, 0, "axes", "needs five axes");
    int a = 0;
    for (const auto& ax : axes) {
      model.axes[a].without_ff = ax.at("without_ff").get<ModelCoefficients>();
      model.axes[a].full_ff = ax.at("full_ff").get<ModelCoefficients>();
      model.axes[a].fit_rms = ax.value("fit_rms", 0.0);
      model.axes[a].friction_band = ax.at("friction_band").get<double>();
      if (!(model.axes[a].friction_band > 0)) throw InputError(source, 0, "friction_band", "must be positive");
      model.axes[a].signal_rms = ax.value("test_rms", 0.0);
      ++a;
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, 0, "", fmt::format("not a five-axis tracking-error model: {}", e.what()));
  }
  return model;
}

}  // namespace trueaxis::fiveaxis
