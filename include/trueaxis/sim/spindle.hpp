#pragma once
// VirtualSpindle: a motor spindle's thermal behaviour and axial growth over
// time (docs/vision.md). Independent of VirtualMachine so other users (a
// virtual camera, a virtual tool) can put it to work on their own clock.
//
// Heat: front and rear bearing losses ∝ (rpm / reference_rpm)^heat_speed_exponent,
// motor losses = idle + ∝ (rpm / reference_rpm)^2 while turning. A lumped RC
// network (ThermalNetwork) carries it: bearings ↔ shaft segments ↔ housing ↔
// ambient, with shaft convection rising with speed.
//
// Growth (truth): the shaft is held axially at its rear (fixed) bearing; the
// nose moves by α·(L_front·(T_front − T_std) + L_rear·(T_rear − T_std)), the
// front segment being the part between the fixed bearing's side and the nose
// that carries the marker. The seed-001 marker sits on the front segment, so
// its strain is α·(T_front − T_std): a reading that assumes the whole spindle
// strains like the marker (Czs = Czb·K) misses the rear segment's difference,
// which the tests and bench/results/vision.md report as the method's own limit.
//
// Sign (docs/sign-convention.md): the nose grows towards the table (−Z on a
// vertical spindle), so the Z error at the tool is −GrowthUm().
#include <string>
#include <vector>

#include "trueaxis/sim/thermal_network.hpp"

namespace trueaxis::sim {

struct SpindleDescription {
  double standard_temp_c = 20.0;     // temperature of the standard sizes (Czb, CBb)
  double length_mm = 300.0;          // Czb: fixed bearing to nose, at standard temperature
  double front_length_mm = 120.0;    // the nose segment that carries the marker (≤ length_mm)
  double diameter_mm = 80.0;         // shaft diameter at the marker
  double expansion_per_k = 11.5e-6;  // α of the shaft (steel)
  double reference_rpm = 10000.0;
  double front_bearing_heat_w = 90.0;  // at reference_rpm
  double rear_bearing_heat_w = 45.0;
  double heat_speed_exponent = 1.5;
  double motor_heat_w = 120.0;       // at reference_rpm
  double motor_idle_heat_w = 5.0;    // while turning at any speed
  double shaft_front_capacity_j_per_k = 4000.0;
  double shaft_rear_capacity_j_per_k = 6000.0;
  double bearing_capacity_j_per_k = 1500.0;
  double motor_capacity_j_per_k = 9000.0;
  double housing_capacity_j_per_k = 60000.0;
  double bearing_to_shaft_w_per_k = 6.0;
  double bearing_to_housing_w_per_k = 4.0;
  double motor_to_shaft_w_per_k = 3.0;
  double motor_to_housing_w_per_k = 5.0;
  double shaft_segments_w_per_k = 1.5;
  double housing_to_ambient_w_per_k = 12.0;
  double shaft_to_ambient_w_per_k = 0.4;          // at rest
  double shaft_to_ambient_rotating_w_per_k = 2.5; // extra at reference_rpm (∝ rpm^0.8)
  double ramp_rpm_per_s = 2000.0;                 // acceleration of speed changes

  bool IsValid(std::string* why) const;
};

// Piecewise-constant speed program: from start_s on, run at rpm (until the next step).
struct SpindleSpeedStep {
  double start_s = 0;
  double rpm = 0;
};

class SpindleSpeedProgram {
 public:
  SpindleSpeedProgram() = default;
  // Steps must start at increasing times ≥ 0 with 0 ≤ rpm ≤ 60000; throws std::invalid_argument.
  explicit SpindleSpeedProgram(std::vector<SpindleSpeedStep> steps);
  // "0:0,1800:9000,14400:4000" (seconds:rpm); throws std::invalid_argument naming the bad item.
  static SpindleSpeedProgram Parse(const std::string& text);
  // A heating/steady/cooling day of `hours`: idle, warm-up at high speed,
  // a steady machining mix, then standstill (cooling) for the last 40 %.
  static SpindleSpeedProgram HeatingCoolingDay(double hours);

  double RpmAt(double t_s) const;  // commanded speed (0 before the first step)
  const std::vector<SpindleSpeedStep>& steps() const { return steps_; }
  std::string ToString() const;

 private:
  std::vector<SpindleSpeedStep> steps_;
};

class VirtualSpindle {
 public:
  // Starts at t = 0, at rest and soaked at ambient_c.
  VirtualSpindle(SpindleDescription description, SpindleSpeedProgram program, double ambient_c = 20.0);

  // Advances the clock by dt_s (speed ramps, rotation, heat).
  void Advance(double dt_s);
  void AdvanceTo(double t_s) { if (t_s > t_s_) Advance(t_s - t_s_); }
  void SetAmbientC(double ambient_c);
  // Feed hold / machine stop: the spindle runs down to 0 rpm and stays there
  // (whatever the program says) until released.
  void Hold(bool on) { hold_ = on; }
  bool held() const { return hold_; }

  double TimeS() const { return t_s_; }
  double Rpm() const { return rpm_; }
  double AngleDeg() const { return angle_deg_; }  // rotation angle of the shaft, [0, 360)

  // ---- truth ---------------------------------------------------------------
  double GrowthUm() const;          // Δz: axial growth of the nose, + = longer spindle
  double ZErrorUm() const { return -GrowthUm(); }  // error at the tool of a vertical spindle
  double MarkerStrain() const;      // K − 1 of the marker (axial = circumferential, isotropic)
  double MarkerScale() const { return 1.0 + MarkerStrain(); }  // true K
  double FrontShaftC() const;
  double RearShaftC() const;
  double FrontBearingC() const;
  double MotorC() const;
  double HousingC() const;

  const SpindleDescription& description() const { return d_; }
  const SpindleSpeedProgram& program() const { return program_; }

 private:
  void Step(double dt_s);

  SpindleDescription d_;
  SpindleSpeedProgram program_;
  ThermalNetwork net_;
  std::size_t ambient_ = 0, housing_ = 0, front_bearing_ = 0, rear_bearing_ = 0, motor_ = 0, shaft_front_ = 0,
              shaft_rear_ = 0, convection_front_ = 0, convection_rear_ = 0;
  double t_s_ = 0, rpm_ = 0, angle_deg_ = 0;
  bool hold_ = false;
};

}  // namespace trueaxis::sim
