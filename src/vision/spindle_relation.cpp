// The marker-to-spindle relation from a reference measurement (include/trueaxis/vision/spindle_relation.hpp).
#include "trueaxis/vision/spindle_relation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace trueaxis::vision {
namespace {

double SpeedTerm(double rpm, double reference_rpm) { return std::pow(std::max(rpm, 0.0) / reference_rpm, 2); }

double LagStep(double lag, double value, double dt_s, double tau_s) { return lag + (1.0 - std::exp(-dt_s / tau_s)) * (value - lag); }

}  // namespace

SpindleRelation FitSpindleRelation(const std::vector<SpindleRelationSample>& s) {
  if (s.size() < 10) throw std::invalid_argument(fmt::format("the relation needs ≥ 10 reference samples, got {}", s.size()));
  double rpm_lo = std::numeric_limits<double>::infinity(), rpm_hi = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i > 0 && !(s[i].time_s > s[i - 1].time_s))
      throw std::invalid_argument(fmt::format("reference sample {}: time must increase", i + 1));
    if (!std::isfinite(s[i].marker_um) || !std::isfinite(s[i].reference_um) || !(s[i].rpm >= 0))
      throw std::invalid_argument(fmt::format("reference sample {}: marker, reference and speed must be finite (speed ≥ 0)", i + 1));
    rpm_lo = std::min(rpm_lo, s[i].rpm);
    rpm_hi = std::max(rpm_hi, s[i].rpm);
  }
  // At least two speeds (10 rpm apart), each held for three samples or more: a run at one speed
  // cannot tell the marker's lag from the speed's.
  std::map<long, int> held;
  for (const auto& p : s) ++held[std::lround(p.rpm / 10.0)];
  int levels = 0;
  for (const auto& [rpm, count] : held) levels += count >= 3 ? 1 : 0;
  if (levels < 2 || !(rpm_hi > rpm_lo))
    throw std::invalid_argument("the reference run must change the spindle speed (heat and cool it): at least two speeds "
                                "held for three samples each");
  SpindleRelation best;
  const auto n = static_cast<Eigen::Index>(s.size());
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y(i) = s[static_cast<std::size_t>(i)].reference_um;
  double best_rms = std::numeric_limits<double>::infinity();
  for (double tau = 300; tau <= 8 * 3600 * 1.0001; tau *= 1.25) {
    Eigen::MatrixXd x(n, 3);
    double lm = s[0].marker_um, ls = SpeedTerm(s[0].rpm, best.reference_rpm);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& p = s[static_cast<std::size_t>(i)];
      if (i > 0) {
        const double dt = p.time_s - s[static_cast<std::size_t>(i - 1)].time_s;
        lm = LagStep(lm, p.marker_um, dt, tau);
        ls = LagStep(ls, SpeedTerm(p.rpm, best.reference_rpm), dt, tau);
      }
      x(i, 0) = p.marker_um;
      x(i, 1) = lm;
      x(i, 2) = ls;
    }
    const Eigen::VectorXd b = x.colPivHouseholderQr().solve(y);
    const double rms = std::sqrt((x * b - y).squaredNorm() / static_cast<double>(n));
    if (rms < best_rms) {
      best_rms = rms;
      best.marker_gain = b(0);
      best.marker_lag_gain = b(1);
      best.speed_lag_um = b(2);
      best.tau_s = tau;
    }
  }
  best.calibrated_rpm_max = rpm_hi;
  best.calibration_rms_um = best_rms;
  best.calibration_samples = static_cast<int>(s.size());
  return best;
}

double SpindleRelationPredictor::Push(double time_s, double marker_um, double rpm) {
  const double speed = SpeedTerm(rpm, r_.reference_rpm);
  if (!started_) {
    lag_marker_ = marker_um;
    lag_speed_ = speed;
    started_ = true;
  } else {
    const double dt = std::max(time_s - last_t_, 0.0);
    lag_marker_ = LagStep(lag_marker_, marker_um, dt, r_.tau_s);
    lag_speed_ = LagStep(lag_speed_, speed, dt, r_.tau_s);
  }
  last_t_ = time_s;
  if (rpm > 1.02 * r_.calibrated_rpm_max) beyond_ = true;
  return r_.marker_gain * marker_um + r_.marker_lag_gain * lag_marker_ + r_.speed_lag_um * lag_speed_;
}

std::string SpindleRelationSpeedWarning(const SpindleRelation& r, double max_rpm_seen) {
  if (!(max_rpm_seen > 1.02 * r.calibrated_rpm_max)) return {};
  return fmt::format(
      "the spindle ran at {:.0f} rpm, above the {:.0f} rpm the marker-to-spindle relation was calibrated on: the growth "
      "there is extrapolated (the part of the spindle behind the marker heats more the faster it turns); calibrate again "
      "with a reference run that reaches this speed",
      max_rpm_seen, r.calibrated_rpm_max);
}

}  // namespace trueaxis::vision
