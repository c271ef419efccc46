#include "trueaxis/signal/channel_filter.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace trueaxis::signal {

bool FilterOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  auto window_ok = [](int w) { return w >= 1 && w <= kMaxFilterWindow && w % 2 == 1; };
  if (!window_ok(hampel_window))
    return fail(fmt::format("hampel_window must be odd and 1..{}, got {}", kMaxFilterWindow, hampel_window));
  if (!window_ok(median_window))
    return fail(fmt::format("median_window must be odd and 1..{}, got {}", kMaxFilterWindow, median_window));
  if (!(hampel_k > 0)) return fail("hampel_k must be > 0");
  if (!(hampel_min_threshold_c >= 0)) return fail("hampel_min_threshold_c must be >= 0");
  if (!(lowpass_time_constant_s >= 0) || !std::isfinite(lowpass_time_constant_s))
    return fail("lowpass_time_constant_s must be a finite value >= 0");
  return true;
}

double MedianOf(const double* values, int n) {
  std::array<double, kMaxFilterWindow> tmp;
  std::copy(values, values + n, tmp.begin());
  const int mid = n / 2;
  std::nth_element(tmp.begin(), tmp.begin() + mid, tmp.begin() + n);
  double m = tmp[mid];
  if (n % 2 == 0) m = 0.5 * (m + *std::max_element(tmp.begin(), tmp.begin() + mid));
  return m;
}

ChannelFilter::ChannelFilter(const FilterOptions& options)
    : options_(options),
      buffer_(static_cast<std::size_t>(std::clamp(options.hampel_window, 1, kMaxFilterWindow) +
                                       std::clamp(options.median_window, 1, kMaxFilterWindow))) {
  PointRings();
}

void ChannelFilter::PointRings() {
  raw_.data = buffer_.data();
  despiked_.data = buffer_.data() + std::clamp(options_.hampel_window, 1, kMaxFilterWindow);
}

void ChannelFilter::Reset() {
  std::fill(buffer_.begin(), buffer_.end(), 0.0);
  raw_.size = raw_.next = 0;
  despiked_.size = despiked_.next = 0;
  lowpass_c_ = 0;
  count_ = 0;
}

ChannelFilter::Output ChannelFilter::Process(double sample_c, double dt_s) {
  Output out;
  // 1. Hampel spike rejection.
  double accepted = sample_c;
  if (options_.hampel_window > 1) {
    raw_.Push(sample_c, options_.hampel_window);
    if (raw_.size >= 3) {
      const double m = MedianOf(raw_.data, raw_.size);
      std::array<double, kMaxFilterWindow> dev;
      for (int i = 0; i < raw_.size; ++i) dev[i] = std::abs(raw_.data[i] - m);
      const double mad = MedianOf(dev.data(), raw_.size);
      const double threshold = std::max(options_.hampel_k * 1.4826 * mad, options_.hampel_min_threshold_c);
      if (std::abs(sample_c - m) > threshold) {
        accepted = m;
        out.spike_rejected = true;
      }
    }
  }
  // 2. Median.
  double despiked = accepted;
  if (options_.median_window > 1) {
    despiked_.Push(accepted, options_.median_window);
    despiked = MedianOf(despiked_.data, despiked_.size);
  }
  // 3. First-order low-pass.
  if (count_ == 0 || options_.lowpass_time_constant_s <= 0) {
    lowpass_c_ = despiked;
  } else {
    const double dt = std::max(dt_s, 0.0);
    const double a = 1.0 - std::exp(-dt / options_.lowpass_time_constant_s);
    lowpass_c_ += a * (despiked - lowpass_c_);
  }
  ++count_;
  out.despiked_c = despiked;
  out.value_c = lowpass_c_;
  return out;
}

}  // namespace trueaxis::signal
