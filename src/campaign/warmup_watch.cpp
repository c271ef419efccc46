#include "trueaxis/campaign/warmup_watch.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"

namespace trueaxis::campaign {

std::string WarmUpStatus::Text() const {
  if (!has_cold) return fmt::format("{}: no cold test yet (campaign add … --axis {} --state cold)", axis, axis);
  if (!has_nut) return fmt::format("{}: no {}_nut readings since the cold test", axis, LowerAscii(axis));
  const std::string head = fmt::format("{}: nut {:+.2f} °C vs cold, {} warm-up test{}", axis, rise_c, taken, taken == 1 ? "" : "s");
  if (complete) return head + ": warm-up complete";
  if (saturated) return head + ": thermal saturation reached, take the last warm-up test now";
  if (due) return head + fmt::format(": next warm-up test due now (at {:+.2f} °C)", next_rise_c);
  std::string s = head + fmt::format(": next test at {:+.2f} °C", next_rise_c);
  if (machining_left_s > 0) s += fmt::format(" and after {:.0f} min more machining", std::ceil(machining_left_s / 60));
  return s;
}

WarmUpStatus WatchWarmUp(const sim::WarmUpRule& rule, double min_warmup_per_test, const nlohmann::ordered_json& measurements,
                         const std::string& axis, std::span<const double> time_s, std::span<const double> nut_c,
                         std::span<const double> travel_mm, double period_s) {
  WarmUpStatus st;
  st.axis = axis;
  const std::string nut = LowerAscii(axis) + "_nut";
  // The last cold test of the axis and the warm-up tests after it.
  struct Test {
    double start_s, end_s, rise_c;
  };
  double cold_end = 0, nut0 = std::nan("");
  std::vector<Test> warm;
  if (measurements.is_array())
    for (const auto& e : measurements) {
      if (!e.is_object() || e.value("axis", std::string()) != axis) continue;
      const std::string state = e.value("state", std::string());
      const double start = e.value("start_time_s", 0.0), end = e.value("end_time_s", start);
      if (state == "cold") {
        st.has_cold = true;
        cold_end = end;
        nut0 = std::nan("");
        if (e.contains("mean_temperatures_c") && e["mean_temperatures_c"].contains(nut) &&
            e["mean_temperatures_c"][nut].is_number())
          nut0 = e["mean_temperatures_c"][nut].get<double>();
        warm.clear();
      } else if (state == "warm" && st.has_cold) {
        warm.push_back({start, end, e.value("nut_rise_c", 0.0)});
      }
    }
  if (!st.has_cold) return st;
  st.taken = static_cast<int>(warm.size());
  st.complete = st.taken >= rule.max_measurements;
  if (!std::isfinite(nut0)) return st;
  // 1-minute means of the nut after the cold test, outside the tests; warm-up seconds exclude them.
  sim::WarmUpCurve curve, before_last;
  std::vector<double> since_last;  // 1-minute means since the last test's end
  const double last_start = warm.empty() ? cold_end : warm.back().start_s;
  const double last_end = warm.empty() ? cold_end : warm.back().end_s;
  double machined_s = 0;
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    const double t = time_s[i];
    if (t <= cold_end || !std::isfinite(nut_c[i])) continue;
    double in_tests = 0;
    bool inside = false;
    for (const auto& w : warm) {
      if (t >= w.start_s && t <= w.end_s) inside = true;
      if (t > w.end_s) in_tests += w.end_s - w.start_s;
    }
    if (inside) continue;
    double sum = 0;
    int n = 0;
    for (std::size_t j = i + 1; j-- > 0 && time_s[j] > t - 60;)
      if (std::isfinite(nut_c[j])) sum += nut_c[j], ++n;
    const double mean = sum / n;
    const double warm_s = t - cold_end - in_tests;
    curve.emplace_back(warm_s, mean - nut0);
    if (t <= last_start) before_last.emplace_back(warm_s, mean - nut0);
    if (t > last_end) {
      since_last.push_back(mean);
      if (i > 0 && travel_mm[i] > travel_mm[i - 1]) machined_s += time_s[i] - time_s[i - 1];
    }
  }
  if (curve.empty()) return st;
  st.has_nut = true;
  st.rise_c = curve.back().second;
  st.next_rise_c = sim::NextTestRise(rule, before_last, warm.empty() ? 0 : warm.back().rise_c, st.taken);
  const double last_duration = warm.empty() ? 0 : warm.back().end_s - warm.back().start_s;
  st.machining_left_s = std::max(0.0, min_warmup_per_test * last_duration - machined_s);
  if (st.complete) return st;
  st.saturated = sim::WarmUpSaturated(rule, since_last, period_s);
  st.due = !st.saturated && std::abs(st.rise_c) >= st.next_rise_c && st.machining_left_s <= 0 &&
           sim::ThresholdTestAllowed(rule, st.taken);
  return st;
}

}  // namespace trueaxis::campaign
