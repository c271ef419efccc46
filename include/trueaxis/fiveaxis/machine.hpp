#pragma once
// A five-axis machine description (TOML, docs/fiveaxis.md): kinematics,
// rotary ranges, the CNC interpolator's limits and, per drive, the cascaded
// servo loop and the mechanics it moves. Linear axes are in mm, rotary in deg;
// every TOML key carries its unit.
#include <string>

#include "trueaxis/fiveaxis/kinematics.hpp"

namespace trueaxis::fiveaxis {

// One drive: position P loop → velocity PI loop → current loop (first-order
// lag, saturating) → motor + screw/gear → load. Motor-side SI units; the load
// is in kg, N·s/m, N (linear) or kg·m², N·m·s/rad, N·m (rotary).
struct DriveParams {
  bool rotary = false;
  double kp_per_s = 40;                    // position loop gain
  double kv_a_s_per_rad = 1.5;             // velocity loop proportional gain
  double ti_s = 0.01;                      // velocity loop integral time
  double current_lag_s = 0.0003;           // current loop time constant
  double kt_nm_per_a = 1.0;                // torque constant
  double current_limit_a = 40;             // saturation (an alarm when reached)
  double motor_inertia_kg_m2 = 1e-3;       // motor + screw (seed 004: j)
  double motor_viscous_n_m_s_per_rad = 2e-3;  // motor + screw (seed 004: b)
  double load_inertia = 300;               // kg (linear) | kg·m² (rotary)   (seed 004: m)
  double load_viscous = 200;               // N·s/m | N·m·s/rad               (seed 004: c)
  double coulomb = 100;                    // N | N·m
  double transmission = 10;                // lead mm/rev (linear) | gear ratio motor rev per rev (rotary)
  double max_velocity_per_s = 500;         // mm/s | deg/s (interpolator limit)

  // Motor rad per axis unit (mm or deg) and per load SI unit (m or rad).
  double MotorRadPerUnit() const;
  double MotorRadPerSi() const;
  double UnitPerSi() const { return rotary ? 57.29577951308232 : 1000.0; }
  // Load reflected to the motor, plus the motor.
  double TotalInertiaKgM2() const;
  double TotalViscousNmsPerRad() const;
  double CoulombAtMotorNm() const;
};

struct InterpolatorLimits {
  double path_accel_mm_per_s2 = 2000;      // tangential (tool tip) acceleration
  double path_jerk_mm_per_s3 = 40000;      // tangential jerk
  double corner_stop_deg = 10;             // a direction change above this is an exact stop
  double rapid_feed_mm_per_min = 20000;    // G0
};

struct FiveAxisMachine {
  std::string name = "five-axis machine";
  std::string source;
  KinematicsParams kinematics;
  double tilt_min_deg = -120, tilt_max_deg = 120;
  double rot_min_deg = -1e6, rot_max_deg = 1e6;  // C: continuous unless limited
  // Travel of the linear joints X, Y, Z (machine coordinates, mm): the plausibility bound unless the file says.
  Eigen::Vector3d travel_min_mm = Eigen::Vector3d::Constant(-1e5), travel_max_mm = Eigen::Vector3d::Constant(1e5);
  double servo_rate_hz = 2000;
  InterpolatorLimits interpolator;
  std::array<DriveParams, kAxisCount> drives;

  std::array<std::string, kAxisCount> axis_names() const { return AxisNames(kinematics.family); }
};

// Parses a machine TOML; InputError names source, line and key.
FiveAxisMachine ParseFiveAxisMachineToml(const std::string& text, const std::string& source);
FiveAxisMachine ReadFiveAxisMachineFile(const std::string& path);

}  // namespace trueaxis::fiveaxis
