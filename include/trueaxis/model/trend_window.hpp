#pragma once
// TrendWindow: the least-squares slope of a signal over a trailing time window, kept sample by
// sample in a fixed number of time bins — no allocation, O(1) per sample and O(kBins) once per
// bin — so a real-time step can follow a temperature's course (the seed-001 heating / steady /
// cooling interval, thermal::ClassifyTrend) at any sample rate.
//
// Each bin keeps the sums of its samples (count, t, v, t², t·v about the bin's first sample), so
// the slope over the bins in the window equals the least-squares slope over their samples. A bin
// is in the window when its first sample is no older than window_s: with samples at least a bin
// apart (a recording, a slow sensor) that is exactly the trailing-window rule of
// thermal::TemperatureTrendCPerH; with faster samples the window's oldest edge moves in steps of
// one bin (window_s / kBins).
//
// The slope is evaluated when a sample opens a new bin (Push returns true) and held until the
// next: with fast samples the trend is at most one bin old.
#include <array>
#include <cstddef>
#include <cstdint>

namespace trueaxis::model {

class TrendWindow {
 public:
  static constexpr std::size_t kBins = 128;

  // Sets the window and restarts. window_s must be > 0.
  void Configure(double window_s);
  double window_s() const { return window_s_; }
  void Reset();
  // Adds a sample. A sample not after the previous one (time went backwards, a duplicate)
  // restarts the window at it. Returns true when the trend was re-evaluated.
  bool Push(double time_s, double value);

  double SlopePerH() const { return slope_per_h_; }  // 0 while fewer than 3 samples
  std::size_t Samples() const { return samples_; }   // samples in the window at the last evaluation
  double SpanS() const { return span_s_; }           // newest − oldest sample time in it

 private:
  struct Bin {
    std::int64_t id = -1;  // floor(t / bin width); -1 = empty
    double t0 = 0;         // time of the bin's first sample (the sums are about it)
    double n = 0, sr = 0, sv = 0, srr = 0, srv = 0;
  };
  void Evaluate(double now_s, std::int64_t now_id);

  double window_s_ = 0, bin_s_ = 0;
  std::array<Bin, kBins + 2> bins_{};
  bool any_ = false;
  double last_t_ = 0;
  double slope_per_h_ = 0, span_s_ = 0;
  std::size_t samples_ = 0;
};

}  // namespace trueaxis::model
