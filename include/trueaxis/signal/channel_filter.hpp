#pragma once
// ChannelFilter: the de-noising chain of one temperature channel (seed 000
// "平穩預處理": remove vibration noise and interference, a stable ±0.1 °C):
//
//   sample -> Hampel spike rejection -> median -> first-order low-pass -> value
//
// 1. Hampel: over the last `hampel_window` raw samples (including this one)
//    take the median m and MAD; when |x - m| > max(hampel_k·1.4826·MAD,
//    hampel_min_threshold_c) the sample is a spike and is replaced by m.
//    The floor keeps a perfectly quiet (quantised) signal from calling every
//    ADC step a spike.
// 2. Median over the last `median_window` Hampel outputs (removes what is left
//    of short bursts, keeps steps sharp).
// 3. Low-pass y += a·(x - y), a = 1 - exp(-dt/tau): dt is the actual time
//    between samples, so irregular cycles filter consistently.
//
// State lives in one buffer sized by the options when the filter is made
// (hampel_window + median_window samples, not kMaxFilterWindow each: a
// workshop server holds a filter per channel of thousands of machines):
// Process() never allocates, so the filter runs inside the real-time cycle.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace trueaxis::signal {

inline constexpr int kMaxFilterWindow = 31;

struct FilterOptions {
  int hampel_window = 9;                 // samples, odd, 3..kMaxFilterWindow; 1 disables
  double hampel_k = 3.0;                 // threshold in robust standard deviations
  double hampel_min_threshold_c = 0.3;   // never call a deviation smaller than this a spike
  int median_window = 5;                 // samples, odd, 1 (off) .. kMaxFilterWindow
  double lowpass_time_constant_s = 5.0;  // 0 disables the low-pass

  bool IsValid(std::string* why) const;
  // No de-noising: every sample passes as it is (the fault rules still judge it).
  static FilterOptions PassThrough() { return {1, 3.0, 0.3, 1, 0.0}; }
};

class ChannelFilter {
 public:
  ChannelFilter() : ChannelFilter(FilterOptions{}) {}
  explicit ChannelFilter(const FilterOptions& options);

  struct Output {
    double value_c = 0;         // filtered value
    double despiked_c = 0;      // after spike rejection and median, before the low-pass
    bool spike_rejected = false;
  };
  // dt_s: time since the previous sample (ignored for the first one).
  Output Process(double sample_c, double dt_s);
  void Reset();
  bool primed() const { return count_ > 0; }
  ChannelFilter(const ChannelFilter& o) : options_(o.options_), buffer_(o.buffer_), raw_(o.raw_), despiked_(o.despiked_),
                                          lowpass_c_(o.lowpass_c_), count_(o.count_) { PointRings(); }
  ChannelFilter& operator=(const ChannelFilter& o) {
    if (this != &o) *this = ChannelFilter(o);
    return *this;
  }
  ChannelFilter(ChannelFilter&& o) noexcept = default;  // the vector's buffer moves with its pointers
  ChannelFilter& operator=(ChannelFilter&& o) noexcept = default;
  double value_c() const { return lowpass_c_; }
  const FilterOptions& options() const { return options_; }

 private:
  // The last `window` samples, in `data` (a slice of buffer_).
  struct Ring {
    double* data = nullptr;
    int size = 0;
    int next = 0;
    void Push(double v, int window) {
      data[next] = v;
      next = (next + 1) % window;
      if (size < window) ++size;
    }
  };
  void PointRings();  // the rings' slices of buffer_ (after a construction, copy or move)

  FilterOptions options_;
  std::vector<double> buffer_;  // the raw ring's hampel_window samples, then the despiked ring's median_window
  Ring raw_;
  Ring despiked_;
  double lowpass_c_ = 0;
  long long count_ = 0;
};

// Median of values[0..n) without allocation (copies into a local array); n <= kMaxFilterWindow.
double MedianOf(const double* values, int n);

}  // namespace trueaxis::signal
