// Seed 004 tracking-error model: derivatives, prediction, feed-forward choice, JSON.
#include "trueaxis/fiveaxis/tracking_model.hpp"

#include <algorithm>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"

namespace trueaxis::fiveaxis {
namespace {
constexpr const char* kModelFormat = "trueaxis five-axis tracking-error model (seed 004)";
}  // namespace

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

namespace {
std::vector<double> DirectionFromVelocity(std::vector<double> v, double friction_band) {
  for (double& x : v) x = std::tanh(x / friction_band);
  return v;
}
}  // namespace

std::vector<double> DirectionOfMotion(const std::vector<double>& position, double dt_s, double derivative_window_s,
                                      double friction_band) {
  return DirectionFromVelocity(SavitzkyGolay(position, dt_s, HalfWindowSamples(derivative_window_s, dt_s)).v,
                               friction_band);
}

void KautzBank(const std::vector<double>& x, double dt_s, const DriveMode& mode, int count, std::vector<double>* out) {
  // Discrete Kautz filters (Wahlberg 1994) of the pole pair p, p̄ = exp(s·dt): the denominator
  // z² + b(c − 1)z − c with c = −|p|², b = 2 Re p / (1 + |p|²); each further pair through the all-pass
  // (−c z² + b(c − 1) z + 1) / (z² + b(c − 1) z − c). Orthonormal, so well conditioned at any rate.
  const double w = 2 * std::numbers::pi * mode.frequency_hz, zeta = std::clamp(mode.damping, 0.0, 1.0);
  const std::complex<double> p = std::exp(std::complex<double>(-zeta * w, w * std::sqrt(1 - zeta * zeta)) * dt_s);
  const double c = -std::norm(p), b = 2 * p.real() / (1 + std::norm(p));
  const double d1 = b * (c - 1), d2 = -c;  // denominator 1 + d1 z⁻¹ + d2 z⁻²
  const double g1 = std::sqrt(1 - c * c), g2 = std::sqrt((1 - c * c) * (1 - b * b));
  const std::size_t n = x.size();
  std::vector<double> in = x, pass(n);
  for (int k = 0; k + 1 < count; k += 2) {
    std::vector<double>& y1 = out[k];
    std::vector<double>& y2 = out[k + 1];
    y1.assign(n, 0.0);
    y2.assign(n, 0.0);
    double w1 = 0, w2 = 0;  // direct form II state
    for (std::size_t i = 0; i < n; ++i) {
      const double w0 = in[i] - d1 * w1 - d2 * w2;
      y1[i] = g1 * (w1 - b * w2);
      y2[i] = g2 * w2;
      pass[i] = -c * w0 + d1 * w1 + w2;
      w2 = w1;
      w1 = w0;
    }
    in.swap(pass);
  }
}

std::array<std::vector<double>, kModelTerms> ModelRegressors(const std::vector<double>& command, double dt_s,
                                                             double derivative_window_s, double friction_band,
                                                             const DriveMode& mode,
                                                             const std::vector<double>* direction_from) {
  Derivatives d = SavitzkyGolay(command, dt_s, HalfWindowSamples(derivative_window_s, dt_s));
  std::array<std::vector<double>, kModelTerms> r;
  // Direction of motion, turning over within the friction band.
  const std::vector<double> sign = direction_from
                                       ? DirectionOfMotion(*direction_from, dt_s, derivative_window_s, friction_band)
                                       : DirectionFromVelocity(d.v, friction_band);
  LaguerreBank(d.a, dt_s, &r[kSeedTerms], kLagTerms);
  LaguerreBank(sign, dt_s, &r[kSeedTerms + kLagTerms], kFrictionTerms);
  if (mode.present()) {
    KautzBank(d.a, dt_s, mode, kModeTerms, &r[kModelTermsWithoutMode]);
    KautzBank(sign, dt_s, mode, kModeFrictionTerms, &r[kModelTermsWithoutMode + kModeTerms]);
  }
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

int UsedTerms(const TrackingErrorModel& model, const AxisErrorModel& axis) {
  if (!model.with_extensions) return kSeedTerms;
  return axis.mode.present() ? kModelTerms : kModelTermsWithoutMode;
}

}  // namespace

std::vector<AxisVector> PredictTrackingError(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                             double dt_s, double kf, const std::vector<AxisVector>* direction_from) {
  std::vector<AxisVector> e(command.size(), AxisVector{});
  for (int a = 0; a < kAxisCount; ++a) {
    const std::vector<double> direction = direction_from ? Column(*direction_from, a) : std::vector<double>{};
    const auto r = ModelRegressors(Column(command, a), dt_s, model.derivative_window_s, model.axes[a].friction_band,
                                   model.axes[a].mode, direction_from ? &direction : nullptr);
    const auto c = model.axes[a].At(kf);
    for (int t = 0; t < UsedTerms(model, model.axes[a]); ++t)
      for (std::size_t i = 0; i < command.size(); ++i) e[i][a] += c[t] * r[t][i];
  }
  return e;
}

FeedForwardChoice ChooseFeedForward(const TrackingErrorModel& model, const std::vector<AxisVector>& command, double dt_s) {
  FeedForwardChoice choice;
  double sum = 0;
  int count = 0;
  for (int a = 0; a < kAxisCount; ++a) {
    choice.per_axis[a] = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> column = Column(command, a);
    // An axis that stands, or moves only by the numerical noise of the inverse kinematics (a rotary
    // axis held at 0° by atan2 of tiny numbers), takes no part: its kf would be noise's.
    if (column.empty() || *std::max_element(column.begin(), column.end()) - *std::min_element(column.begin(), column.end()) <
                              kStandingAxisRange)
      continue;
    const auto& ax = model.axes[a];
    const auto r = ModelRegressors(column, dt_s, model.derivative_window_s, ax.friction_band, ax.mode);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < command.size(); ++i) {
      double e0 = 0, e1 = 0;
      for (int t = 0; t < UsedTerms(model, ax); ++t) {
        e0 += ax.without_ff[t] * r[t][i];
        e1 += ax.full_ff[t] * r[t][i];
      }
      num += e0 * (e1 - e0);
      den += (e1 - e0) * (e1 - e0);
    }
    if (den <= 1e-30) continue;  // the axis's error does not depend on kf
    choice.per_axis[a] = -num / den;
    sum += choice.per_axis[a];
    ++count;
  }
  choice.averaged = count > 0 ? sum / count : 0.0;
  return choice;
}

std::vector<std::string> ModelFitWarnings(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names) {
  std::vector<std::string> out;
  for (int a = 0; a < kAxisCount; ++a) {
    const auto& ax = model.axes[a];
    if (!(ax.signal_rms > 0) || ax.fit_rms <= kPoorFitFraction * ax.signal_rms) continue;
    out.push_back(fmt::format(
        "axis {}: the tracking-error model leaves {:.1f} % of its identification run's tracking error unexplained "
        "(fit residual {:.4g} of {:.4g} RMS; a well-described axis: under {:.0f} %): the drive behaves beyond the model "
        "(e.g. more than one lightly damped mode, or a drive at its current limit), so the correction will remove markedly less of "
        "the contour error than usual; check the drive's tuning and identify again",
        names[a], 100.0 * ax.fit_rms / ax.signal_rms, ax.fit_rms, ax.signal_rms, 100.0 * kPoorFitFraction));
  }
  return out;
}

std::string ModelToJson(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names) {
  nlohmann::ordered_json j;
  j["format"] = kModelFormat;
  j["derivative_window_s"] = model.derivative_window_s;
  j["with_extensions"] = model.with_extensions;
  j["terms"] =
      "v, a, j, 10 Laguerre filters of a, 8 of tanh(v / friction_band), pole 10 ms; 4 Kautz filters of a, 4 of "
      "tanh(v / friction_band) at the axis's drive mode (mode_hz, mode_damping; mode_hz 0: none)";
  for (int a = 0; a < kAxisCount; ++a) {
    const auto& ax = model.axes[a];
    j["axes"].push_back({{"axis", names[a]}, {"without_ff", ax.without_ff}, {"full_ff", ax.full_ff},
                         {"friction_band", ax.friction_band}, {"mode_hz", ax.mode.frequency_hz},
                         {"mode_damping", ax.mode.damping}, {"fit_rms", ax.fit_rms}, {"test_rms", ax.signal_rms}});
  }
  return j.dump(2) + "\n";
}

namespace {

// Largest |coefficient| a model may hold. Identified values are tiny (c_v =
// (1 − kf)/Kp ≤ 10 s for Kp ≥ 0.1/s; the friction terms are mm); anything
// near this would predict metres of tracking error.
constexpr double kMaxPlausibleCoefficient = 1e3;
// Savitzky–Golay window of v, a, j: identify writes 0.01 s.
constexpr double kMaxDerivativeWindowS = 1.0;
// Drive mode: above this it would be no slow mode (and beyond any servo rate's Nyquist frequency).
constexpr double kMaxModeHz = 1000.0;

// Reads one field of the model file, refusing what is missing or of the wrong type.
class ModelReader {
 public:
  explicit ModelReader(const std::string& source) : source_(source) {}
  [[noreturn]] void Fail(const std::string& field, const std::string& message) const {
    throw InputError(source_, 0, field, message);
  }
  const nlohmann::json& At(const nlohmann::json& j, const std::string& path, const std::string& key) const {
    const std::string field = path.empty() ? key : path + "." + key;
    if (!j.is_object() || !j.contains(key)) Fail(field, "required field is missing");
    return j.at(key);
  }
  double Number(const nlohmann::json& j, const std::string& path, const std::string& key) const {
    const nlohmann::json& v = At(j, path, key);
    if (!v.is_number()) Fail(path.empty() ? key : path + "." + key, "expected a number");
    return v.get<double>();
  }
  // `terms`: kModelTerms, or kModelTermsWithoutMode for a model written before the drive mode.
  ModelCoefficients Coefficients(const nlohmann::json& j, const std::string& path, const std::string& key,
                                 int terms) const {
    const std::string field = path + "." + key;
    const nlohmann::json& v = At(j, path, key);
    if (!v.is_array() || v.size() != static_cast<std::size_t>(terms))
      Fail(field,
           terms == kModelTerms
               ? fmt::format("expected an array of {} numbers (v, a, j, {} lag, {} friction, {} + {} drive-mode terms), got {}",
                             kModelTerms, kLagTerms, kFrictionTerms, kModeTerms, kModeFrictionTerms,
                             v.is_array() ? std::to_string(v.size()) : "no array")
               : fmt::format("expected an array of {} numbers (v, a, j, {} lag and {} friction terms: a model without "
                             "mode_hz, written before the drive mode), got {}",
                             kModelTermsWithoutMode, kLagTerms, kFrictionTerms,
                             v.is_array() ? std::to_string(v.size()) : "no array"));
    ModelCoefficients c{};
    for (int i = 0; i < terms; ++i) {
      const std::string item = fmt::format("{}[{}]", field, i);
      if (!v[i].is_number()) Fail(item, "expected a number");
      c[i] = v[i].get<double>();
      if (!std::isfinite(c[i]) || std::abs(c[i]) > kMaxPlausibleCoefficient)
        Fail(item, fmt::format("{:g} is not a plausible tracking-error coefficient (|c| ≤ {:g})", c[i],
                               kMaxPlausibleCoefficient));
    }
    return c;
  }

 private:
  const std::string& source_;
};

}  // namespace

TrackingErrorModel ModelFromJson(const std::string& text, const std::string& source,
                                 const std::array<std::string, kAxisCount>& machine_axes) {
  const nlohmann::json j = ParseJsonOrThrow(text, source);
  const ModelReader r(source);
  if (!j.is_object()) r.Fail("", "not a five-axis tracking-error model (expected a JSON object)");
  const nlohmann::json& format = r.At(j, "", "format");
  if (!format.is_string() || format.get<std::string>() != kModelFormat)
    r.Fail("format", fmt::format("expected \"{}\" (a model written by `fiveaxis identify`)", kModelFormat));
  TrackingErrorModel model;
  model.derivative_window_s = r.Number(j, "", "derivative_window_s");
  if (!(model.derivative_window_s > 0 && model.derivative_window_s <= kMaxDerivativeWindowS))
    r.Fail("derivative_window_s", fmt::format("{:g} s is outside 0 … {:g} s (identify writes 0.01 s)",
                                              model.derivative_window_s, kMaxDerivativeWindowS));
  if (j.contains("with_extensions")) {
    if (!j["with_extensions"].is_boolean()) r.Fail("with_extensions", "expected true or false");
    model.with_extensions = j["with_extensions"].get<bool>();
  }
  const nlohmann::json& axes = r.At(j, "", "axes");
  if (!axes.is_array() || axes.size() != kAxisCount)
    r.Fail("axes", fmt::format("needs five axes ({})", fmt::join(machine_axes, " ")));
  for (int a = 0; a < kAxisCount; ++a) {
    const nlohmann::json& ax = axes[a];
    const std::string path = fmt::format("axes[{}]", a);
    const nlohmann::json& name = r.At(ax, path, "axis");
    if (!name.is_string() || name.get<std::string>() != machine_axes[a])
      r.Fail(path + ".axis", fmt::format("'{}' where the machine's axis {} is {} (axes in the order {}); was the model "
                                         "identified on another machine?",
                                         name.is_string() ? name.get<std::string>() : name.dump(), a + 1, machine_axes[a],
                                         fmt::join(machine_axes, " ")));
    AxisErrorModel& m = model.axes[a];
    // A model written before the drive mode has no mode_hz and 21 coefficients: it reads as a model without a mode.
    const bool has_mode_fields = ax.is_object() && ax.contains("mode_hz");
    if (has_mode_fields) {
      m.mode.frequency_hz = r.Number(ax, path, "mode_hz");
      if (!(m.mode.frequency_hz >= 0 && m.mode.frequency_hz <= kMaxModeHz))
        r.Fail(path + ".mode_hz", fmt::format("{:g} Hz is outside 0 … {:g} Hz (0: no drive mode)", m.mode.frequency_hz,
                                              kMaxModeHz));
      if (m.mode.present()) {
        m.mode.damping = r.Number(ax, path, "mode_damping");
        if (!(m.mode.damping > 0 && m.mode.damping <= 1))
          r.Fail(path + ".mode_damping", fmt::format("{:g} is outside 0 … 1", m.mode.damping));
      }
    }
    const int terms = has_mode_fields ? kModelTerms : kModelTermsWithoutMode;
    m.without_ff = r.Coefficients(ax, path, "without_ff", terms);
    m.full_ff = r.Coefficients(ax, path, "full_ff", terms);
    m.friction_band = r.Number(ax, path, "friction_band");
    if (!(m.friction_band > 0) || !std::isfinite(m.friction_band))
      r.Fail(path + ".friction_band", "must be a positive number (mm/s or deg/s)");
    m.fit_rms = ax.contains("fit_rms") ? r.Number(ax, path, "fit_rms") : 0.0;
    m.signal_rms = ax.contains("test_rms") ? r.Number(ax, path, "test_rms") : 0.0;
  }
  return model;
}

}  // namespace trueaxis::fiveaxis
