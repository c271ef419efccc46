#include "trueaxis/thermal/hysteresis_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "json_fields.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal {
namespace {
constexpr std::size_t kMaxSensors = 256;

Eigen::VectorXd ReferenceOf(const ThermalSeries& s, const std::vector<std::string>& names) {
  Eigen::VectorXd ref = Eigen::VectorXd::Zero(s.Rows());
  for (const auto& n : names) {
    auto idx = s.TemperatureIndex(n);
    if (!idx) throw InputError(s.source, 0, n, "reference temperature for the heating/cooling classification is missing");
    ref += s.temperatures_c.col(static_cast<Eigen::Index>(*idx));
  }
  return ref / static_cast<double>(names.size());
}
}  // namespace

bool IntervalClassifierOptions::IsValid(std::string* why) const {
  if (!(window_s > 0) || !(threshold_c_per_h >= 0)) {
    if (why) *why = "classifier needs window_s > 0 and threshold_c_per_h >= 0";
    return false;
  }
  return true;
}

bool HysteresisFitOptions::IsValid(std::string* why) const {
  if (!sub_model.IsValid(why) || !classifier.IsValid(why)) return false;
  if (min_interval_samples < 3) {
    if (why) *why = "min_interval_samples must be >= 3";
    return false;
  }
  return true;
}

std::vector<double> TemperatureTrendCPerH(const std::vector<double>& t, const Eigen::VectorXd& y, double window_s) {
  const std::size_t n = t.size();
  std::vector<double> slope(n, 0.0);
  // Running sums over the trailing window (two pointers), centred on the
  // current time for numerical safety.
  std::size_t lo = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (t[lo] < t[i] - window_s) ++lo;
    const std::size_t m = i - lo + 1;
    if (m < 3) continue;
    double st = 0, sy = 0, stt = 0, sty = 0;
    for (std::size_t k = lo; k <= i; ++k) {
      const double dt = t[k] - t[i];
      st += dt;
      sy += y(static_cast<Eigen::Index>(k));
      stt += dt * dt;
      sty += dt * y(static_cast<Eigen::Index>(k));
    }
    const double mm = static_cast<double>(m);
    const double den = mm * stt - st * st;
    if (den > 0) slope[i] = (mm * sty - st * sy) / den * 3600.0;
  }
  return slope;
}

std::vector<ThermalInterval> ClassifyIntervals(const std::vector<double>& t, const Eigen::VectorXd& y,
                                               const IntervalClassifierOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("classifier options", why);
  std::vector<double> slope = TemperatureTrendCPerH(t, y, o.window_s);
  std::vector<ThermalInterval> out(t.size(), ThermalInterval::kSteady);
  std::size_t lo = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    while (t[lo] < t[i] - o.window_s) ++lo;
    out[i] = ClassifyTrend(slope[i], i - lo + 1, t[i] - t[lo], o);
  }
  return out;
}

ThermalInterval ClassifyTrend(double trend_c_per_h, std::size_t samples, double span_s,
                              const IntervalClassifierOptions& o) {
  if (samples < 3 || span_s < 0.5 * o.window_s) return ThermalInterval::kStartUp;
  if (trend_c_per_h > o.threshold_c_per_h) return ThermalInterval::kHeating;
  if (trend_c_per_h < -o.threshold_c_per_h) return ThermalInterval::kCooling;
  return ThermalInterval::kSteady;
}

IntervalTracker::IntervalTracker(IntervalClassifierOptions options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw InputError("classifier options", why);
  window_.Configure(options_.window_s);
}

ThermalInterval IntervalTracker::Push(double time_s, double reference_c) {
  window_.Push(time_s, reference_c);
  return ClassifyTrend(window_.SlopePerH(), window_.Samples(), window_.SpanS(), options_);
}

HysteresisThermalModel::HysteresisThermalModel(LinearThermalModel all_data, std::vector<LinearThermalModel> per_interval,
                                               std::vector<bool> interval_fitted,
                                               std::vector<std::string> reference_sensors,
                                               IntervalClassifierOptions classifier)
    : all_data_(std::move(all_data)),
      per_interval_(std::move(per_interval)),
      fitted_(std::move(interval_fitted)),
      reference_(std::move(reference_sensors)),
      classifier_(classifier) {
  BuildMaps();
}

void HysteresisThermalModel::BuildMaps() {
  sensors_.clear();
  maps_.clear();
  auto add = [&](const std::string& n) {
    auto it = std::find(sensors_.begin(), sensors_.end(), n);
    if (it != sensors_.end()) return static_cast<int>(it - sensors_.begin());
    sensors_.push_back(n);
    return static_cast<int>(sensors_.size() - 1);
  };
  for (const auto& r : reference_) add(r);
  for (std::size_t k = 0; k <= per_interval_.size(); ++k) {
    const LinearThermalModel& m = k < per_interval_.size() ? per_interval_[k] : all_data_;
    std::vector<int> map;
    for (const auto& n : m.InputSensors()) map.push_back(add(n));
    maps_.push_back(std::move(map));
  }
  if (sensors_.size() > kMaxSensors)  // Predict gathers into a fixed buffer (no allocation)
    throw InputError("hysteresis model", fmt::format("{} sensors; at most {} are supported", sensors_.size(), kMaxSensors));
}

void HysteresisThermalModel::Predict(const ThermalSample& sample, std::span<double> out_um) const {
  const auto i = static_cast<std::size_t>(sample.interval);
  const std::size_t which = (i < fitted_.size() && fitted_[i]) ? i : per_interval_.size();
  const LinearThermalModel& m = which < per_interval_.size() ? per_interval_[which] : all_data_;
  const std::vector<int>& map = maps_[which];
  std::array<double, kMaxSensors> buf;  // only the first map.size() are read
  for (std::size_t k = 0; k < map.size() && k < kMaxSensors; ++k) buf[k] = sample.temperatures_c[static_cast<std::size_t>(map[k])];
  ThermalSample sub{std::span<const double>(buf.data(), map.size()), sample.position_mm, sample.interval};
  m.Predict(sub, out_um);
}

std::vector<ThermalInterval> HysteresisThermalModel::ClassifyRows(const ThermalSeries& s) const {
  if (!s.has_time)
    throw InputError(s.source, 0, "time_s", "the hysteresis model classifies by temperature trend and needs time_s");
  return ClassifyIntervals(s.time_s, ReferenceOf(s, reference_), classifier_);
}

nlohmann::json HysteresisThermalModel::ToJson() const {
  nlohmann::json subs = nlohmann::json::object();
  for (int i = 0; i < kThermalIntervalCount; ++i)
    subs[ThermalIntervalName(static_cast<ThermalInterval>(i))] =
        fitted_[static_cast<std::size_t>(i)] ? per_interval_[static_cast<std::size_t>(i)].ToJson() : nlohmann::json(nullptr);
  return {{"kind", "hysteresis"},
          {"reference_sensors", reference_},
          {"classifier", {{"window_s", classifier_.window_s}, {"threshold_c_per_h", classifier_.threshold_c_per_h}}},
          {"all_data", all_data_.ToJson()},
          {"intervals", subs}};
}

std::string HysteresisThermalModel::Describe() const {
  std::string out = fmt::format(
      "interval rule: slope of mean({}) over the trailing {} s; heating > +{} °C/h, cooling < -{} °C/h, else steady; "
      "start-up (less than half a window of history) uses the all-data model\n",
      fmt::join(reference_, ", "), classifier_.window_s, classifier_.threshold_c_per_h, classifier_.threshold_c_per_h);
  for (int i = 0; i < kThermalIntervalCount; ++i) {
    out += fmt::format("[{}]\n", ThermalIntervalName(static_cast<ThermalInterval>(i)));
    out += fitted_[static_cast<std::size_t>(i)] ? per_interval_[static_cast<std::size_t>(i)].Describe()
                                                : std::string("  too few training rows: uses the all-data model\n");
  }
  out += "[all data]\n" + all_data_.Describe();
  return out;
}

HysteresisThermalModel HysteresisThermalModel::FromJson(const nlohmann::json& doc, const std::string& source,
                                                        const std::string& path) {
  detail::JsonFields f(source);
  std::vector<std::string> ref = f.Strings(doc, path, "reference_sensors");
  if (ref.empty()) f.Fail(f.Join(path, "reference_sensors"), "needs at least one sensor");
  const auto& cj = f.Get(doc, path, "classifier");
  IntervalClassifierOptions co;
  co.window_s = f.Number(cj, f.Join(path, "classifier"), "window_s");
  co.threshold_c_per_h = f.Number(cj, f.Join(path, "classifier"), "threshold_c_per_h");
  std::string why;
  if (!co.IsValid(&why)) f.Fail(f.Join(path, "classifier"), why);
  LinearThermalModel all = LinearThermalModel::FromJson(f.Get(doc, path, "all_data"), source, f.Join(path, "all_data"));
  const auto& ij = f.Get(doc, path, "intervals");
  std::vector<LinearThermalModel> subs(kThermalIntervalCount);
  std::vector<bool> fitted(kThermalIntervalCount, false);
  for (int i = 0; i < kThermalIntervalCount; ++i) {
    const std::string key = ThermalIntervalName(static_cast<ThermalInterval>(i));
    const auto& j = f.Get(ij, f.Join(path, "intervals"), key);
    if (j.is_null()) continue;
    const std::string p = f.Join(f.Join(path, "intervals"), key);
    subs[static_cast<std::size_t>(i)] = LinearThermalModel::FromJson(j, source, p);
    if (subs[static_cast<std::size_t>(i)].Channels() != all.Channels())
      f.Fail(p, "sub-model channels differ from the all-data model's");
    fitted[static_cast<std::size_t>(i)] = true;
  }
  return HysteresisThermalModel(std::move(all), std::move(subs), std::move(fitted), std::move(ref), co);
}

HysteresisThermalModel FitHysteresisModel(const ThermalSeries& s, const HysteresisFitOptions& o,
                                          std::vector<std::string>* warnings) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("hysteresis fit options", why);
  if (!s.has_time)
    throw InputError(s.source, 0, "time_s", "the hysteresis model classifies by temperature trend and needs time_s");
  auto warn = [&](std::string text) {
    if (warnings) warnings->push_back(std::move(text));
  };
  // A trend needs several samples in its window, whatever the recording's sample interval.
  IntervalClassifierOptions classifier = o.classifier;
  if (s.Rows() >= 2) {
    const double median_step_s = MedianTimeStepS(s);
    if (classifier.window_s < kMinWindowSteps * median_step_s) {
      classifier.window_s = kMinWindowSteps * median_step_s;
      warn(fmt::format("hysteresis: the sample interval is {:g} s, so the {:g} s trend window would hold fewer than {} "
                       "samples; widened to {:g} s (the classifier reacts that much later)",
                       median_step_s, o.classifier.window_s, kMinWindowSteps, classifier.window_s));
    }
  }
  LinearThermalModel all = FitLinearModel(s, o.sub_model);
  std::vector<std::string> ref = o.reference_sensors.empty() ? all.InputSensors() : o.reference_sensors;
  std::vector<ThermalInterval> cls = ClassifyIntervals(s.time_s, ReferenceOf(s, ref), classifier);
  std::vector<LinearThermalModel> subs(kThermalIntervalCount);
  std::vector<bool> fitted(kThermalIntervalCount, false);
  const auto start_up = static_cast<std::size_t>(std::count(cls.begin(), cls.end(), ThermalInterval::kStartUp));
  // Rows whose window holds less than half its span are start-up whatever the trend: when they are
  // most of the training rows, that (not the threshold) is why an interval is short of rows.
  if (2 * start_up > cls.size())
    warn(fmt::format("hysteresis: {} of {} training rows are start-up (less than half of the {:g} s trend window of "
                     "history: the {:g} s recorded per run are too short for the window), so the heating, steady and "
                     "cooling intervals have few rows; check the unit of the time column (--time-unit)",
                     start_up, cls.size(), classifier.window_s, LongestExperimentS(s)));
  for (int i = 0; i < kThermalIntervalCount; ++i) {
    std::vector<Eigen::Index> rows;
    for (std::size_t r = 0; r < cls.size(); ++r)
      if (cls[r] == static_cast<ThermalInterval>(i)) rows.push_back(static_cast<Eigen::Index>(r));
    if (static_cast<int>(rows.size()) < o.min_interval_samples) {
      warn(fmt::format("hysteresis: only {} training rows are {} ({}); that interval uses the all-data model", rows.size(),
                       ThermalIntervalName(static_cast<ThermalInterval>(i)),
                       2 * start_up > cls.size()
                           ? fmt::format("{} rows are start-up", start_up)
                           : fmt::format("the trend never passes ±{:g} °C/h long enough", classifier.threshold_c_per_h)));
      continue;
    }
    subs[static_cast<std::size_t>(i)] = FitLinearModel(SelectRows(s, rows), o.sub_model);
    fitted[static_cast<std::size_t>(i)] = true;
  }
  return HysteresisThermalModel(std::move(all), std::move(subs), std::move(fitted), std::move(ref), classifier);
}

}  // namespace trueaxis::thermal
