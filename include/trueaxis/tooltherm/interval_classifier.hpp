#pragma once
// Seed 001's interval sub-model: is the tool heating (WT1), steady (WT2) or
// cooling (WT3)? (docs/tool-thermal.md, "Interval classifier").
//
// The trend of Tv is the least-squares slope over the trailing window_s
// (thermal::IntervalTracker, the same rule as the series hysteresis model);
// |slope| ≤ dead_band_c_per_h is steady. A new class is taken only after the
// raw class has held it for dwell_s (minimum dwell), so noise near the dead
// band's edge does not make the interval chatter. Until the window holds
// half its span after a (re)start the class is kStartUp.
//
// The options are chosen from the data, not fixed: SeriesStatisticsOf()
// measures the sample interval and the noise of Tv (from second differences),
// and ClassifierOptionsFor() sets the window in sample steps (≥ 5 steps) and
// the dead band to at least 3σ of the slope that noise alone gives over that
// window, so a steady tool reads steady at any noise and sample interval.
#include <string>
#include <vector>

#include "trueaxis/thermal/hysteresis_model.hpp"

namespace trueaxis::tooltherm {

using thermal::ThermalInterval;

struct ToolClassifierOptions {
  double window_s = 120;
  double dead_band_c_per_h = 30;
  double dwell_s = 60;

  bool IsValid(std::string* why) const;
};

struct SeriesStatistics {
  double sample_s = 0;   // median time step
  double noise_c = 0;    // 1σ of the sample-to-sample noise (robust, from second differences)
};
// Needs ≥ 3 samples with increasing time (std::invalid_argument otherwise).
SeriesStatistics SeriesStatisticsOf(const std::vector<double>& time_s, const std::vector<double>& value_c);

// 1σ of the window slope (°C/h) that white noise of noise_c gives with samples every sample_s.
double NoiseSlopeCPerH(const SeriesStatistics& s, double window_s);

// window = max(window_steps, 5) sample steps; dead band = max(3·NoiseSlopeCPerH, min_dead_band_c_per_h);
// dwell = max(window / 2, 2 sample steps).
ToolClassifierOptions ClassifierOptionsFor(const SeriesStatistics& s, double window_steps, double min_dead_band_c_per_h);

// The whole choice from a recorded course (restart marks each mounting): the shortest window of
// 5·2^k sample steps (k = 0…6) over which the noise slope (3σ) stays under a quarter of the
// 90th percentile of |slope| (the course's own heating/cooling rate); dead band =
// max(3σ noise slope, 0.1 · that percentile).
ToolClassifierOptions ChooseClassifierOptions(const std::vector<double>& time_s, const std::vector<double>& tv_c,
                                              const std::vector<bool>& restart);
// 90th percentile of |trailing-window slope| (°C/h) of a course.
double SlopePercentileCPerH(const std::vector<double>& time_s, const std::vector<double>& tv_c,
                            const std::vector<bool>& restart, double window_s, double p = 0.9);

class DwellIntervalClassifier {
 public:
  explicit DwellIntervalClassifier(ToolClassifierOptions options);
  ThermalInterval Push(double time_s, double tv_c);
  void Reset();  // a tool change: the new tool's course starts anew
  double TrendCPerH() const { return tracker_.TrendCPerH(); }
  ThermalInterval current() const { return current_; }
  // The window actually used: widened to 5 sample steps when the samples come more
  // coarsely than the options were chosen for (else the trend could never be measured).
  double window_s() const { return window_s_; }

 private:
  ToolClassifierOptions options_;
  thermal::IntervalTracker tracker_;
  double window_s_ = 0, dwell_s_ = 0, last_time_s_ = 0;
  bool has_last_ = false;
  ThermalInterval current_ = ThermalInterval::kStartUp;
  ThermalInterval candidate_ = ThermalInterval::kStartUp;
  double candidate_since_s_ = 0;
};

// The classes of a whole series; restart[i] marks the first sample after a tool change.
std::vector<ThermalInterval> ClassifySeries(const std::vector<double>& time_s, const std::vector<double>& tv_c,
                                            const std::vector<bool>& restart, const ToolClassifierOptions& options);

}  // namespace trueaxis::tooltherm
