#include "trueaxis/modelfit/motion_heat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trueaxis::model {

std::vector<double> MotionHeatAtPoints(const measure::Measurement& m, const TemperatureHistory& history, double tau_s) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> out(m.points.size(), kNaN);
  if (!(tau_s > 0) || !history.HasTravel()) return out;
  const auto& t = history.travel_time_s;
  const auto& d = history.travel_mm;
  // M at each row, and the feed over the interval that ends there.
  std::vector<double> at_row(t.size(), 0.0), feed(t.size(), 0.0);
  for (std::size_t r = 1; r < t.size(); ++r) {
    const double dt = t[r] - t[r - 1];
    feed[r] = dt > 0 ? std::abs(d[r] - d[r - 1]) / dt * 0.06 : 0.0;  // mm/s → m/min
    at_row[r] = dt > 0 ? feed[r] + (at_row[r - 1] - feed[r]) * std::exp(-dt / tau_s) : at_row[r - 1];
  }
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    if (!m.points[i].time_s) continue;
    const double now = *m.points[i].time_s;
    // The row at or before the point; the feed of the interval it lies in, held.
    const auto it = std::upper_bound(t.begin(), t.end(), now);
    if (it == t.begin()) continue;  // before the history: unknown
    const auto r = static_cast<std::size_t>(it - t.begin()) - 1;
    const double v = r + 1 < t.size() ? feed[r + 1] : 0.0;  // past the last row: at rest
    out[i] = v + (at_row[r] - v) * std::exp(-(now - t[r]) / tau_s);
  }
  return out;
}

}  // namespace trueaxis::model
