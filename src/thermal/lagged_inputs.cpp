#include "trueaxis/thermal/lagged_inputs.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::thermal {
namespace {

// The lag of one column over the whole series, restarting at experiments and long gaps.
Eigen::VectorXd LagColumn(const ThermalSeries& s, const Eigen::VectorXd& raw, double tau_s) {
  const double reset_gap_s = kLagResetGapFactor * MedianTimeStepS(s);
  Eigen::VectorXd out(raw.size());
  InputLagFilter f(tau_s);
  for (Eigen::Index r = 0; r < raw.size(); ++r) {
    const auto ru = static_cast<std::size_t>(r);
    if (r > 0 && (s.ExperimentOf(r) != s.ExperimentOf(r - 1) || s.time_s[ru] - s.time_s[ru - 1] > reset_gap_s))
      f.Reset();
    out(r) = f.Push(s.time_s[ru], raw(r));
  }
  return out;
}

}  // namespace

std::vector<double> DefaultLagGridS() { return {600, 1800, 5400, 16200}; }

LagStartUp LagStartUpRows(const ThermalSeries& s, const std::vector<std::string>& inputs) {
  LagStartUp out;
  for (const auto& name : inputs) {
    double tau = 0;
    if (ParseLaggedName(name, nullptr, &tau)) out.longest_tau_s = std::max(out.longest_tau_s, tau);
  }
  if (out.longest_tau_s == 0 || !s.has_time) return out;
  out.settle_s = kLagSettleTaus * out.longest_tau_s;
  const double reset_gap_s = kLagResetGapFactor * MedianTimeStepS(s);
  double start_s = 0;
  for (Eigen::Index r = 0; r < s.Rows(); ++r) {
    const auto ru = static_cast<std::size_t>(r);
    if (r == 0 || s.ExperimentOf(r) != s.ExperimentOf(r - 1) || s.time_s[ru] - s.time_s[ru - 1] > reset_gap_s) {
      start_s = s.time_s[ru];
      ++out.starts;
    }
    if (s.time_s[ru] - start_s < out.settle_s) ++out.rows;
  }
  return out;
}

std::string LaggedName(const std::string& sensor, double tau_s) { return fmt::format("{}@lag{:g}s", sensor, tau_s); }

bool ParseLaggedName(const std::string& name, std::string* sensor, double* tau_s) {
  const auto at = name.rfind("@lag");
  if (at == std::string::npos || name.size() < at + 6 || name.back() != 's') return false;
  const auto tau = ParseDouble(std::string_view(name).substr(at + 4, name.size() - at - 5));
  if (!tau || !(*tau > 0)) return false;
  if (sensor) *sensor = name.substr(0, at);
  if (tau_s) *tau_s = *tau;
  return true;
}

double InputLagFilter::Push(double time_s, double reading_c) {
  if (!started_ || !(time_s > last_time_s_)) {
    started_ = true;
    value_c_ = reading_c;
  } else {
    value_c_ += (reading_c - value_c_) * (1.0 - std::exp(-(time_s - last_time_s_) / tau_s_));
  }
  last_time_s_ = time_s;
  return value_c_;
}

ThermalSeries AddLaggedTemperatures(const ThermalSeries& s, const std::vector<double>& taus_s,
                                    std::vector<double>* skipped) {
  if (!s.has_time && !taus_s.empty())
    throw InputError(s.source, 0, "time_s", "lagged temperature inputs need time_s");
  ThermalSeries out = s;
  // The longest single experiment: a lag is identified within one run, so five 6-hour runs support
  // the lags a 6-hour run does, not those of 30 hours.
  const double duration_s = LongestExperimentS(s);
  std::vector<std::size_t> raw;
  for (std::size_t k = 0; k < s.temperature_names.size(); ++k)
    if (!ParseLaggedName(s.temperature_names[k], nullptr, nullptr)) raw.push_back(k);
  std::vector<double> used;
  for (double tau : taus_s) {
    if (!(tau > 0) || !std::isfinite(tau)) throw InputError("lag grid", fmt::format("{} s is not a time constant", tau));
    if (tau > duration_s / 3) {
      if (skipped) skipped->push_back(tau);
      continue;
    }
    used.push_back(tau);
  }
  const Eigen::Index base = out.temperatures_c.cols();
  out.temperatures_c.conservativeResize(Eigen::NoChange, base + static_cast<Eigen::Index>(used.size() * raw.size()));
  Eigen::Index col = base;
  for (double tau : used)
    for (std::size_t k : raw) {
      out.temperature_names.push_back(LaggedName(s.temperature_names[k], tau));
      out.temperatures_c.col(col++) = LagColumn(s, s.temperatures_c.col(static_cast<Eigen::Index>(k)), tau);
    }
  return out;
}

ThermalSeries WithLaggedInputs(const ThermalSeries& s, const std::vector<std::string>& needed) {
  std::vector<std::pair<std::string, std::pair<std::string, double>>> missing;
  for (const auto& name : needed) {
    std::string sensor;
    double tau = 0;
    if (s.TemperatureIndex(name) || !ParseLaggedName(name, &sensor, &tau)) continue;
    if (!s.TemperatureIndex(sensor))
      throw InputError(s.source, 0, sensor, fmt::format("the model's input '{}' lags sensor '{}', which the series lacks",
                                                        name, sensor));
    if (!s.has_time) throw InputError(s.source, 0, "time_s", fmt::format("the model's input '{}' needs time_s", name));
    missing.push_back({name, {sensor, tau}});
  }
  if (missing.empty()) return s;
  ThermalSeries out = s;
  const Eigen::Index base = out.temperatures_c.cols();
  out.temperatures_c.conservativeResize(Eigen::NoChange, base + static_cast<Eigen::Index>(missing.size()));
  for (std::size_t m = 0; m < missing.size(); ++m) {
    out.temperature_names.push_back(missing[m].first);
    const auto idx = static_cast<Eigen::Index>(*s.TemperatureIndex(missing[m].second.first));
    out.temperatures_c.col(base + static_cast<Eigen::Index>(m)) = LagColumn(s, s.temperatures_c.col(idx), missing[m].second.second);
  }
  return out;
}

}  // namespace trueaxis::thermal
