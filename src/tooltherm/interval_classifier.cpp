#include "trueaxis/tooltherm/interval_classifier.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::tooltherm {
namespace {

double Median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

bool ToolClassifierOptions::IsValid(std::string* why) const {
  if (window_s > 0 && dead_band_c_per_h >= 0 && dwell_s >= 0 && std::isfinite(window_s + dead_band_c_per_h + dwell_s))
    return true;
  if (why) *why = "window_s must be > 0, dead_band_c_per_h and dwell_s ≥ 0";
  return false;
}

SeriesStatistics SeriesStatisticsOf(const std::vector<double>& t, const std::vector<double>& y) {
  if (t.size() != y.size() || t.size() < 3) throw std::invalid_argument("series statistics need ≥ 3 samples");
  std::vector<double> dt, d2;
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (!(t[i] > t[i - 1])) continue;  // a restart: time runs on in another tool's course
    dt.push_back(t[i] - t[i - 1]);
    if (i + 1 < t.size() && t[i + 1] > t[i]) d2.push_back(y[i + 1] - 2 * y[i] + y[i - 1]);
  }
  if (dt.empty() || d2.empty()) throw std::invalid_argument("series statistics need increasing time");
  SeriesStatistics s;
  s.sample_s = Median(dt);
  const double med = Median(d2);
  for (double& v : d2) v = std::abs(v - med);
  s.noise_c = 1.4826 * Median(d2) / std::sqrt(6.0);  // var(second difference) = 6σ² for white noise
  return s;
}

double NoiseSlopeCPerH(const SeriesStatistics& s, double window_s) {
  const double n = std::max(3.0, std::floor(window_s / s.sample_s) + 1);
  return s.noise_c * std::sqrt(12.0 / (n * (n * n - 1))) / s.sample_s * 3600.0;
}

ToolClassifierOptions ClassifierOptionsFor(const SeriesStatistics& s, double window_steps, double min_dead_band_c_per_h) {
  ToolClassifierOptions o;
  o.window_s = std::max(window_steps, 5.0) * s.sample_s;
  o.dead_band_c_per_h = std::max(3.0 * NoiseSlopeCPerH(s, o.window_s), min_dead_band_c_per_h);
  o.dwell_s = std::max(0.5 * o.window_s, 2.0 * s.sample_s);
  return o;
}

double SlopePercentileCPerH(const std::vector<double>& t, const std::vector<double>& tv, const std::vector<bool>& restart,
                            double window_s, double p) {
  thermal::IntervalTracker tracker({window_s, 0});
  std::vector<double> slopes;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (restart[i]) tracker.Reset();
    if (tracker.Push(t[i], tv[i]) != ThermalInterval::kStartUp) slopes.push_back(std::abs(tracker.TrendCPerH()));
  }
  if (slopes.empty()) return 0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(slopes.size() - 1));
  std::nth_element(slopes.begin(), slopes.begin() + static_cast<long>(k), slopes.end());
  return slopes[k];
}

ToolClassifierOptions ChooseClassifierOptions(const std::vector<double>& t, const std::vector<double>& tv,
                                              const std::vector<bool>& restart) {
  const SeriesStatistics s = SeriesStatisticsOf(t, tv);
  ToolClassifierOptions o;
  for (double steps = 5; steps <= 320; steps *= 2) {
    o = ClassifierOptionsFor(s, steps, 0);
    const double p90 = SlopePercentileCPerH(t, tv, restart, o.window_s);
    o.dead_band_c_per_h = std::max(o.dead_band_c_per_h, 0.1 * p90);
    if (3 * NoiseSlopeCPerH(s, o.window_s) <= 0.25 * p90) break;
  }
  return o;
}

DwellIntervalClassifier::DwellIntervalClassifier(ToolClassifierOptions options)
    : options_(options), tracker_({options.window_s, options.dead_band_c_per_h}), window_s_(options.window_s), dwell_s_(options.dwell_s) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("interval classifier: " + why);
}

void DwellIntervalClassifier::Reset() {
  tracker_.Reset();
  current_ = candidate_ = ThermalInterval::kStartUp;
  candidate_since_s_ = 0;
  has_last_ = false;
}

ThermalInterval DwellIntervalClassifier::Push(double time_s, double tv_c) {
  if (has_last_ && time_s > last_time_s_ && 5 * (time_s - last_time_s_) > window_s_) {
    window_s_ = 5 * (time_s - last_time_s_);  // coarser samples than the options were made for
    dwell_s_ = std::max(options_.dwell_s, 0.5 * window_s_);
    tracker_ = thermal::IntervalTracker({window_s_, options_.dead_band_c_per_h});
    current_ = candidate_ = ThermalInterval::kStartUp;
  }
  has_last_ = true;
  last_time_s_ = time_s;
  const ThermalInterval raw = tracker_.Push(time_s, tv_c);
  if (raw == ThermalInterval::kStartUp) {  // (re)start: no trend yet
    current_ = candidate_ = raw;
    return current_;
  }
  if (current_ == ThermalInterval::kStartUp) {  // first trend: nothing to hold on to
    current_ = candidate_ = raw;
    return current_;
  }
  if (raw == current_) {
    candidate_ = current_;
  } else if (raw != candidate_) {
    candidate_ = raw;
    candidate_since_s_ = time_s;
  }
  if (candidate_ != current_ && time_s - candidate_since_s_ >= dwell_s_) current_ = candidate_;
  return current_;
}

std::vector<ThermalInterval> ClassifySeries(const std::vector<double>& t, const std::vector<double>& tv,
                                            const std::vector<bool>& restart, const ToolClassifierOptions& options) {
  DwellIntervalClassifier c(options);
  std::vector<ThermalInterval> out;
  out.reserve(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (restart[i]) c.Reset();
    out.push_back(c.Push(t[i], tv[i]));
  }
  return out;
}

}  // namespace trueaxis::tooltherm
