#include "trueaxis/sim/interpolator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace trueaxis::sim {

std::optional<FeedForward> ParseFeedForward(std::string_view text) {
  if (text == "off") return FeedForward::kOff;
  if (text == "ahead") return FeedForward::kAhead;
  if (text == "late") return FeedForward::kLate;
  return std::nullopt;
}

std::string_view FeedForwardName(FeedForward f) {
  switch (f) {
    case FeedForward::kOff: return "off";
    case FeedForward::kAhead: return "ahead";
    case FeedForward::kLate: return "late";
  }
  return "off";
}

bool InterpolatorOptions::IsValid(std::string* why) const {
  auto fail = [why](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (!(cycle_s >= 1e-4 && cycle_s <= 0.1)) return fail("cycle_s: must be 0.1–100 ms (CNCs: 1–4 ms)");
  if (fine_steps < 1 || fine_steps > 64) return fail("fine_steps: must be 1–64");
  return true;
}

void MoveStats::Merge(const MoveStats& o) {
  cycles += o.cycles;
  samples += o.samples;
  sum_sq_following += o.sum_sq_following;
  max_abs_following_um = std::max(max_abs_following_um, o.max_abs_following_um);
  max_abs_position_error_um = std::max(max_abs_position_error_um, o.max_abs_position_error_um);
  rms_following_um = samples > 0 ? std::sqrt(sum_sq_following / static_cast<double>(samples)) : 0.0;
}

CncInterpolator::CncInterpolator(VirtualMachine& vm, std::size_t axis, InterpolatorOptions options,
                                 AxisCorrectionFn correction)
    : vm_(vm), axis_(axis), o_(options), correction_(std::move(correction)) {
  std::string why;
  if (!o_.IsValid(&why)) throw std::invalid_argument("interpolator options: " + why);
  if (o_.mode != FeedForward::kOff && !correction_) throw std::invalid_argument("interpolator: a correction is required");
  if (axis_ >= vm_.AxisCount()) throw std::invalid_argument("interpolator: no such axis");
  dir_ = vm_.ServoDirection(axis_) < 0 ? -1 : 1;
  applied_um_ = vm_.CorrectionUm(axis_);
  all_corrections_.resize(vm_.AxisCount());
}

double CncInterpolator::Correction(double x_mm, int dir) const {
  return o_.mode == FeedForward::kOff ? 0.0 : correction_(x_mm, dir);
}

void CncInterpolator::Write(double correction_um) {
  for (std::size_t i = 0; i < all_corrections_.size(); ++i) all_corrections_[i] = vm_.CorrectionUm(i);
  all_corrections_[axis_] = correction_um;
  vm_.WriteCompensation(all_corrections_);
  applied_um_ = correction_um;
}

// One interpolation cycle: set point from x_from to x_to (commanded), in fine
// sub-steps. kAhead evaluates the correction at every sub-step's set point
// (what the drive's fine interpolator is about to reach; in the first cycle
// after a reversal blended from the correction applied now, while the play is
// taken up); the other modes move it linearly from the one applied now to c_to.
// The following error is sampled at every sub-step's end and middle (the drive
// moves linearly between sub-step set points, so the middle shows the chord),
// in the first cycle after a reversal at the ends only.
void CncInterpolator::Cycle(double x_from, double x_to, double c_to, double dt_s, int dir, bool reversing,
                            MoveStats* stats) {
  const double c_from = applied_um_;
  const int n = o_.fine_steps;
  const double feed = std::abs(x_to - x_from) / dt_s * 60.0;
  const bool every_step = o_.mode == FeedForward::kAhead && x_to != x_from;
  double x_before = x_from, c_before = c_from;
  for (int j = 1; j <= n; ++j) {
    const double f = static_cast<double>(j) / n;
    const double x = x_from + (x_to - x_from) * f;
    double c = c_from + (c_to - c_from) * f;
    if (every_step) c = reversing ? c_from + (Correction(x, dir) - c_from) * f : Correction(x, dir);
    Write(c);
    if (feed > 0) vm_.CommandMove(axis_, x, feed);
    vm_.Advance(dt_s / n);
    if (stats) {
      // Across a reversal the blend is deliberate (the play is being taken up): only the sub-step's end counts.
      const int count = reversing ? 1 : 2;
      const double samples[2] = {c - Correction(vm_.CommandedMm(axis_), dir),
                                 0.5 * (c_before + c) - Correction(0.5 * (x_before + x), dir)};
      for (int k = 0; k < count; ++k) {
        const double following = samples[k];
        ++stats->samples;
        stats->sum_sq_following += following * following;
        stats->max_abs_following_um = std::max(stats->max_abs_following_um, std::abs(following));
      }
      stats->max_abs_position_error_um = std::max(stats->max_abs_position_error_um, std::abs(vm_.ErrorUm(axis_)));
    }
    x_before = x;
    c_before = c;
  }
  if (stats) ++stats->cycles;
}

MoveStats CncInterpolator::MoveTo(double target_mm, double feed_mm_min) {
  if (!(feed_mm_min > 0)) throw std::invalid_argument("interpolator: feed must be positive");
  MoveStats stats;
  double x = vm_.CommandedMm(axis_);
  const double dist = target_mm - x;
  if (std::abs(dist) < 1e-9) return stats;
  const int dir = dist > 0 ? 1 : -1;
  const double step = feed_mm_min / 60.0 * o_.cycle_s;
  while (std::abs(target_mm - x) > 1e-9) {
    const double left = std::abs(target_mm - x);
    const double d = std::min(step, left);
    const double x_next = d >= left ? target_mm : x + dir * d;
    // kAhead: the interval about to be travelled; kLate: the position already
    // reached, with the direction known when it was reached.
    const double c_next = o_.mode == FeedForward::kLate ? Correction(x, dir_) : Correction(x_next, dir);
    Cycle(x, x_next, c_next, o_.cycle_s * d / step, dir, dir != dir_, &stats);
    dir_ = dir;
    x = x_next;
  }
  stats.rms_following_um = stats.samples > 0 ? std::sqrt(stats.sum_sq_following / static_cast<double>(stats.samples)) : 0.0;
  return stats;
}

void CncInterpolator::Dwell(double dwell_s) {
  if (!(dwell_s > 0)) return;
  const double x = vm_.CommandedMm(axis_);
  // One cycle brings the correction to that of the position reached (kLate's
  // last step), then the axis simply stands.
  const double first = std::min(dwell_s, o_.cycle_s);
  Cycle(x, x, Correction(x, dir_), first, dir_, false, nullptr);
  if (dwell_s > first) vm_.Advance(dwell_s - first);
}

}  // namespace trueaxis::sim
