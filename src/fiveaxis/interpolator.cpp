// CNC interpolator: jerk-limited time law along the programmed path.
#include "trueaxis/fiveaxis/interpolator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::fiveaxis {
namespace {

// Moving average of length n (n >= 1) of a sequence extended with zeros (sum kept).
std::vector<double> MovingAverage(const std::vector<double>& x, int n) {
  if (n <= 1) return x;
  std::vector<double> y(x.size() + n - 1, 0.0);
  double sum = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (i < x.size()) sum += x[i];
    if (i >= static_cast<std::size_t>(n) && i - n < x.size()) sum -= x[i - n];
    y[i] = sum / n;
  }
  return y;
}

double CornerDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (a.norm() < 1e-9 || b.norm() < 1e-9) return 0;
  return AxisAngleRad(a, b) * 180.0 / std::numbers::pi;
}

// The budget of servo periods is exceeded at vertex `at` (the piece from
// there needs `piece_samples` more after `used`): an InputError naming the
// program line (or the option that set a generated path's feed), the move and
// what would fit.
[[noreturn]] void ThrowOverBudget(const ToolPath& path, std::size_t at, double used, double piece_samples, double rate_hz) {
  const PathVertex& v = path.vertices[at];
  const double needed_s = (used + piece_samples) / rate_hz;
  const double budget_s = static_cast<double>(kMaxServoSamples) / rate_hz;
  std::string move;
  if (v.move == MoveKind::kInverseTime) move = fmt::format("an inverse-time block of {:g} s", v.duration_s);
  else if (v.move == MoveKind::kRapid) move = "a rapid (G0) move";
  else move = fmt::format("a move at {:g} mm/min", v.feed_mm_per_min);
  const std::string limit = fmt::format(
      "the simulation holds at most {} servo periods ({:g} s at {:g} Hz) but the path needs {:.4g} s", kMaxServoSamples,
      budget_s, rate_hz, needed_s);
  if (v.source_line > 0) {
    throw InputError(path.name, v.source_line, v.move == MoveKind::kRapid ? "G0" : path.feed_field,
                     fmt::format("{} runs past the limit here: {}; raise the feed or split the program", move, limit));
  }
  const double fitting_feed = v.feed_mm_per_min * needed_s / budget_s;
  throw InputError("command line", 0, path.feed_field,
                   fmt::format("{} at {:g} mm/min: {}; a feed of about {:.3g} mm/min or more fits", path.name,
                               v.feed_mm_per_min, limit, fitting_feed));
}

}  // namespace

std::vector<AxisVector> VertexJoints(const ToolPath& path, const Kinematics& kin) {
  std::vector<AxisVector> q;
  q.reserve(path.vertices.size());
  for (const auto& v : path.vertices) q.push_back(kin.Inverse(v.tip_mm, v.tilt_deg, v.rot_deg));
  return q;
}

Trajectory Interpolate(const ToolPath& path, const FiveAxisMachine& m, double settle_s) {
  const Kinematics kin(m.kinematics);
  Trajectory t;
  t.dt_s = 1.0 / m.servo_rate_hz;
  const auto& v = path.vertices;
  if (v.empty()) return t;
  const std::vector<AxisVector> q = VertexJoints(path, kin);
  const int settle = static_cast<int>(std::lround(settle_s / t.dt_s));
  auto emit = [&](std::size_t seg, double fraction) {  // point on segment seg (v[seg-1] → v[seg])
    const PathVertex& a = v[seg - 1];
    const PathVertex& b = v[seg];
    t.joints.push_back(kin.Inverse(a.tip_mm + fraction * (b.tip_mm - a.tip_mm),
                                   a.tilt_deg + fraction * (b.tilt_deg - a.tilt_deg),
                                   a.rot_deg + fraction * (b.rot_deg - a.rot_deg)));
  };
  for (int i = 0; i < settle; ++i) t.joints.push_back(q[0]);

  // Nominal duration and nominal tip speed of each segment.
  const std::size_t n = v.size();
  std::vector<double> duration(n, 0.0), speed(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    if (v[k].move == MoveKind::kInverseTime) {
      duration[k] = v[k].duration_s;
      continue;
    }
    const double feed = (v[k].move == MoveKind::kRapid ? m.interpolator.rapid_feed_mm_per_min : v[k].feed_mm_per_min) / 60;
    double d = (v[k].tip_mm - v[k - 1].tip_mm).norm() / feed;
    for (int a = 0; a < kAxisCount; ++a) d = std::max(d, std::abs(q[k][a] - q[k - 1][a]) / m.drives[a].max_velocity_per_s);
    duration[k] = d;
    speed[k] = feed;
  }
  // Each axis's speed at full rate, as a fraction of its limit: a jump of
  // more than kJointJump between segments (a corner in joint space, e.g. a
  // rotary swing near a singular orientation) is an exact stop too.
  constexpr double kJointJump = 0.2;
  auto joint_jump = [&](std::size_t s) {
    if (duration[s] <= 0 || duration[s - 1] <= 0) return false;
    for (int a = 0; a < kAxisCount; ++a) {
      const double before = (q[s - 1][a] - q[s - 2][a]) / duration[s - 1] / m.drives[a].max_velocity_per_s;
      const double after = (q[s][a] - q[s - 1][a]) / duration[s] / m.drives[a].max_velocity_per_s;
      if (std::abs(after - before) > kJointJump) return true;
    }
    return false;
  };
  // Pieces: a new one where the kind of move or the feed changes, or at a sharp corner.
  std::size_t k = 1;
  while (k < n) {
    std::size_t end = k + 1;
    while (end < n && v[end].move == v[k].move && v[end].feed_mm_per_min == v[k].feed_mm_per_min &&
           (v[k].move == MoveKind::kInverseTime ||
            (CornerDeg(v[end - 1].tip_mm - v[end - 2].tip_mm, v[end].tip_mm - v[end - 1].tip_mm) <=
                 m.interpolator.corner_stop_deg &&
             !joint_jump(end))))
      ++end;
    double total = 0;
    for (std::size_t s = k; s < end; ++s) total += duration[s];
    if (total > 0) {
      // Rate of nominal time per real time: 1 while moving, shaped by the filters.
      double steps = total / t.dt_s;
      if (std::abs(steps - std::round(steps)) < 1e-6) steps = std::max(1.0, std::round(steps));
      double accel_samples = 1, jerk_samples = 1;
      if (v[k].move != MoveKind::kInverseTime) {
        const double accel_time = speed[k] / m.interpolator.path_accel_mm_per_s2;
        const double jerk_time = m.interpolator.path_accel_mm_per_s2 / m.interpolator.path_jerk_mm_per_s3;
        accel_samples = std::max(1.0, std::round(accel_time / t.dt_s));
        jerk_samples = std::max(1.0, std::round(jerk_time / t.dt_s));
      }
      // Bound the work before allocating: this piece, the rest before it and the final rest.
      const double piece_samples = std::ceil(steps) + accel_samples + jerk_samples - 2;
      const double used = static_cast<double>(t.joints.size());
      if (!(used + piece_samples + settle <= static_cast<double>(kMaxServoSamples))) {
        // Name the vertex whose move crosses the limit.
        std::size_t at = k;
        double before = used;
        while (at + 1 < end && before + duration[at] / t.dt_s <= static_cast<double>(kMaxServoSamples))
          before += duration[at++] / t.dt_s;
        ThrowOverBudget(path, at, used, piece_samples + settle, m.servo_rate_hz);
      }
      std::vector<double> rate(static_cast<std::size_t>(std::ceil(steps)), 1.0);
      rate.back() = steps - std::floor(steps) > 1e-12 ? steps - std::floor(steps) : 1.0;
      rate = MovingAverage(rate, static_cast<int>(accel_samples));
      rate = MovingAverage(rate, static_cast<int>(jerk_samples));
      double tau = 0;
      std::size_t seg = k;
      double seg_start = 0;
      for (double r : rate) {
        tau = std::min(total, tau + r * t.dt_s);
        while (seg + 1 < end && tau > seg_start + duration[seg]) seg_start += duration[seg++];
        emit(seg, duration[seg] > 0 ? std::clamp((tau - seg_start) / duration[seg], 0.0, 1.0) : 1.0);
      }
    }
    k = end;
  }
  for (int i = 0; i < settle; ++i) t.joints.push_back(q[n - 1]);
  return t;
}

}  // namespace trueaxis::fiveaxis
