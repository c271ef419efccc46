// Cascaded P / PI servo drive with current lag, friction and saturation.
#include "trueaxis/fiveaxis/servo_drive.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::fiveaxis {
namespace {
constexpr int kSubSteps = 8;                 // mechanics integrated at 8× the servo rate
constexpr double kStictionBandRadPerS = 0.05;  // Coulomb friction smoothed as tanh(ω / band)
}  // namespace

ServoDrive::ServoDrive(const DriveParams& p, double servo_rate_hz, FeedForward ff, double start_position)
    : p_(p),
      dt_s_(1.0 / servo_rate_hz),
      ff_(ff),
      n_unit_(p.MotorRadPerUnit()),
      j_(p.TotalInertiaKgM2()),
      b_(p.TotalViscousNmsPerRad()),
      fc_(p.CoulombAtMotorNm()),
      position_unit_(start_position),
      r_prev_(start_position) {}

double ServoDrive::Step(double r) {
  // Controller: samples the position at the start of the period (what a drive
  // trace records with the command of that period), holds its output.
  const double measured = position_unit_;
  const double v_ref = first_ ? 0.0 : (r - r_prev_) / dt_s_;  // unit/s, backward difference
  const double a_ref = first_ ? 0.0 : (v_ref - v_ref_prev_) / dt_s_;
  first_ = false;
  r_prev_ = r;
  v_ref_prev_ = v_ref;
  const double omega_ref = n_unit_ * (p_.kp_per_s * (r - position_unit_) + ff_.velocity * v_ref);
  const double omega_error = omega_ref - omega_;
  integral_ += omega_error * dt_s_ / p_.ti_s;
  double current_cmd = p_.kv_a_s_per_rad * (omega_error + integral_) +
                       ff_.acceleration * j_ * n_unit_ * a_ref / p_.kt_nm_per_a;
  if (std::abs(current_cmd) > p_.current_limit_a) {
    current_cmd = std::copysign(p_.current_limit_a, current_cmd);
    integral_ -= omega_error * dt_s_ / p_.ti_s;  // anti-windup: hold the integral while saturated
    ++saturated_;
  }
  // Mechanics, sub-stepped.
  const double h = dt_s_ / kSubSteps;
  const double lag = p_.current_lag_s > 0 ? 1.0 - std::exp(-h / p_.current_lag_s) : 1.0;
  for (int k = 0; k < kSubSteps; ++k) {
    current_ += (current_cmd - current_) * lag;
    // Friction linearised at ω (implicit step: stable for any friction level).
    const double th = std::tanh(omega_ / kStictionBandRadPerS);
    const double friction = fc_ * th, friction_slope = fc_ * (1 - th * th) / kStictionBandRadPerS;
    const double rhs = omega_ + h * (p_.kt_nm_per_a * current_ - friction + friction_slope * omega_) / j_;
    omega_ = rhs / (1.0 + h * (b_ + friction_slope) / j_);
    position_unit_ += h * omega_ / n_unit_;
  }
  return measured;
}

std::vector<double> RunDrive(const DriveParams& p, double servo_rate_hz, FeedForward ff,
                             const std::vector<double>& command, std::int64_t* saturated) {
  std::vector<double> out;
  out.reserve(command.size());
  if (command.empty()) return out;
  ServoDrive drive(p, servo_rate_hz, ff, command.front());
  for (double r : command) out.push_back(drive.Step(r));
  if (saturated) *saturated = drive.saturated_periods();
  return out;
}

}  // namespace trueaxis::fiveaxis
