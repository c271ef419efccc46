#include "trueaxis/model/trend_window.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace trueaxis::model {

void TrendWindow::Configure(double window_s) {
  if (!(window_s > 0) || !std::isfinite(window_s)) throw std::invalid_argument("TrendWindow: window_s must be > 0");
  window_s_ = window_s;
  bin_s_ = window_s / static_cast<double>(kBins);
  Reset();
}

void TrendWindow::Reset() {
  bins_.fill(Bin{});
  any_ = false;
  last_t_ = 0;
  slope_per_h_ = 0;
  span_s_ = 0;
  samples_ = 0;
}

bool TrendWindow::Push(double time_s, double value) {
  if (!(bin_s_ > 0) || !std::isfinite(time_s) || !std::isfinite(value)) return false;
  if (any_ && !(time_s > last_t_)) Reset();
  const auto id = static_cast<std::int64_t>(std::floor(time_s / bin_s_));
  Bin& b = bins_[static_cast<std::size_t>(id % static_cast<std::int64_t>(bins_.size()))];
  const bool new_bin = b.id != id;
  if (new_bin) b = Bin{id, time_s};
  const double r = time_s - b.t0;
  b.n += 1;
  b.sr += r;
  b.sv += value;
  b.srr += r * r;
  b.srv += r * value;
  any_ = true;
  last_t_ = time_s;
  if (new_bin) Evaluate(time_s, id);
  return new_bin;
}

void TrendWindow::Evaluate(double now_s, std::int64_t now_id) {
  // Sums about t = now (as thermal::TemperatureTrendCPerH): t − now = r + c with c = t0 − now.
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0, oldest = now_s;
  const std::int64_t first_id = now_id - static_cast<std::int64_t>(bins_.size()) + 1;
  for (const Bin& b : bins_) {
    if (b.id < first_id || b.id > now_id || b.t0 < now_s - window_s_) continue;
    const double c = b.t0 - now_s;
    n += b.n;
    st += b.sr + b.n * c;
    sv += b.sv;
    stt += b.srr + 2 * c * b.sr + b.n * c * c;
    stv += b.srv + c * b.sv;
    oldest = std::min(oldest, b.t0);
  }
  samples_ = static_cast<std::size_t>(n);
  span_s_ = now_s - oldest;
  slope_per_h_ = 0;
  const double den = n * stt - st * st;
  if (n >= 3 && den > 0) slope_per_h_ = (n * stv - st * sv) / den * 3600.0;
}

}  // namespace trueaxis::model
