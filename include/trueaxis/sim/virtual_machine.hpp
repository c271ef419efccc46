#pragma once
// VirtualMachine: a semi-closed-loop machine tool with ball-screw feed drives,
// its thermal behaviour and its temperature sensors, advanced in simulated
// time (docs/machine-file.md describes the physics and the parameters).
//
// Position physics per axis (error = actual − commanded, docs/sign-convention.md):
//   motor position  m = commanded + correction            (the CNC adds the compensation)
//   actual table    = m + pitch(m, dir) ∓ backlash/2      (play between motor and table)
//                     + growth α∫₀ᵘ(T_screw − 20 °C)ds     (u = distance of m from the fixed end,
//                                                           away from the fixed end)
//                     + bed growth over bed_anchor_mm + homing offset
// The encoder sits on the motor, so none of this is seen by the CNC.
//
// Time: the clock only moves in Advance() (and the blocking helpers built on
// it). Motion is kinematic at the commanded feed; the thermal network and the
// sensors step on a fixed grid of `thermal_step_s`, so results do not depend
// on how Advance() calls are sliced. Deterministic for (description, seed).
//
// Not thread-safe: a server that reads it from another thread must hold a
// mutex around every call (the MODBUS server does).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/sim/ambient_profile.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/pitch_error.hpp"
#include "trueaxis/sim/thermal_network.hpp"
#include "trueaxis/sim/virtual_sensor.hpp"

namespace trueaxis::sim {

class VirtualMachine : public hw::CncLink, public hw::TemperatureSource {
 public:
  // Starts at t = 0 (description.start_iso) with every axis homed at its
  // reference point and the machine soaked at the ambient of the last 24 h.
  VirtualMachine(MachineDescription description, std::uint64_t seed);
  ~VirtualMachine() override;

  const MachineDescription& description() const { return d_; }
  std::uint64_t seed() const { return seed_; }

  // ---- time -------------------------------------------------------------
  double TimeS() const { return t_s_; }               // seconds since start
  double UnixTimeS() const { return start_unix_s_ + t_s_; }
  std::string IsoTime() const;                         // simulated date/time
  // Advances the clock by dt_s: motion, heat, sensors.
  void Advance(double dt_s);
  // Idles (every axis stopped, coolant off) until absolute machine time t_s,
  // integrating in coarse steps without calling the logger. Long gaps
  // (> 36 h) soak the machine at the ambient of the day before and integrate
  // only the last day, so "another day" is cheap.
  void IdleUntil(double t_s);
  // Called every `interval_s` of machine time during Advance (on the grid).
  void SetLogger(double interval_s, std::function<void(const VirtualMachine&)> logger);
  // An in-the-loop controller, called every `interval_s` of machine time
  // during Advance (its own schedule, independent of the thermal step), with
  // write access: a runtime compensator reads CncLink/TemperatureSource and
  // writes compensation here, so it stays active while a laser test or a
  // warm-up runs. nullptr removes it. Note the physics: a correction that
  // changes against the direction of the last motion while the axis stands
  // still first takes up the backlash, as on a real drive — update often
  // enough that corrections change while the axis moves.
  void SetController(double interval_s, std::function<void(VirtualMachine&)> controller);

  // ---- motion programs (non-blocking: they run while time advances) ----
  void CommandMove(std::size_t axis, double target_mm, double feed_mm_min);
  // Back and forth between lo and hi at feed; `duty` < 1 pauses at each end
  // so the axis moves that fraction of the time (a machining duty cycle).
  // `return_feed_mm_min` > 0 runs the return strokes at another feed (2000/4000 alternation).
  void CommandReciprocate(std::size_t axis, double lo_mm, double hi_mm, double feed_mm_min, double duty = 1.0,
                          double return_feed_mm_min = 0);
  void CommandStop(std::size_t axis);
  bool IsMoving(std::size_t axis) const;
  // Blocking helpers: advance time until the move is done / for dwell_s.
  void MoveTo(std::size_t axis, double target_mm, double feed_mm_min);
  void Dwell(double dwell_s) { Advance(dwell_s); }
  // Homes the axis: new homing offset drawn with the homing repeatability.
  void Home(std::size_t axis);
  // The reference error left by the last homing (µm, added to every position
  // of the axis). sim/homing.hpp sets it from its switch / index model.
  double HomingOffsetUm(std::size_t axis) const;
  void SetHomingOffsetUm(std::size_t axis, double offset_um);

  void SetCoolant(CoolantState state) { coolant_ = state; }
  CoolantState coolant() const { return coolant_; }

  // ---- state ------------------------------------------------------------
  double CommandedMm(std::size_t axis) const;       // what the CNC reports
  double ActualMm(std::size_t axis) const;          // where the table really is (20 °C scale)
  double ErrorUm(std::size_t axis) const { return (ActualMm(axis) - CommandedMm(axis)) * 1000.0; }
  double CorrectionUm(std::size_t axis) const;      // compensation currently applied
  int ServoDirection(std::size_t axis) const;       // +1/−1 last motor motion, 0 none yet
  double FeedNowMmMin(std::size_t axis) const;      // current speed (0 at rest)
  // The path the axis has travelled since the start (mm, both directions counted): what a
  // CNC's distance counter gives, and what the motion-heat input of a model integrates.
  double TravelMm(std::size_t axis) const;
  // Model-free truth for tests: error the axis would have at x when
  // approached in `direction`, at the present temperatures.
  double ErrorAtUm(std::size_t axis, double x_mm, int direction) const;
  double ThermalGrowthUm(std::size_t axis, double x_mm) const;  // α∫(T−20)ds part only
  // An error from outside the axis model, added to what the laser and the tool
  // see on that axis (error sign): e.g. VirtualSpindle::ZErrorUm() on Z, set by
  // the caller as the spindle's clock advances (docs/vision.md).
  void SetExtraErrorUm(std::size_t axis, double error_um);

  // True temperatures of the thermal nodes ("x_nut", "x_bearing",
  // "x_floating_bearing", "x_motor", "x_screw_07", "bed", "ambient", "coolant").
  double NodeTemperatureC(const std::string& node) const;
  std::vector<std::string> NodeNames() const;
  double AmbientC() const;
  // Sets every node and probe to temp_c (tests: uniform temperature state).
  void Soak(double temp_c);

  // ---- sensors ------------------------------------------------------------
  std::size_t SensorCount() const { return sensors_.size(); }
  const VirtualSensor& sensor(std::size_t i) const { return *sensors_[i]; }
  int SensorIndex(const std::string& name) const;  // −1 when absent
  // Inject or clear (kind kNone) a fault; false when the sensor is unknown.
  bool SetSensorFault(const std::string& name, const SensorFault& fault);
  // The same at machine time `at_s` (applied on the thermal grid, at the first step at or after
  // it; at once when that is past): a sensor that dies while a program runs. False when unknown.
  bool ScheduleSensorFault(const std::string& name, const SensorFault& fault, double at_s);

  // ---- CNC side -----------------------------------------------------------
  void SetCompensationEnabled(bool on) { compensation_enabled_ = on; }
  bool compensation_enabled() const { return compensation_enabled_; }
  // Simulates a broken link: Read/WriteCompensation return false.
  void SetLinkFault(bool fault) { link_fault_ = fault; }
  // Feed hold (e.g. seed 001's camera stop rule, docs/vision.md): while held every axis stands
  // where it is and the motion programs wait; releasing resumes them. Time and heat go on.
  void SetFeedHold(bool hold) { feed_hold_ = hold; }
  bool FeedHold() const { return feed_hold_; }

  // hw::CncLink
  std::size_t AxisCount() const override { return axes_.size(); }
  std::string AxisName(std::size_t axis) const override;
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override;
  // actual = commanded + correction + error. Ignored (but true) when the
  // CNC-side enable is off; false on link fault or a non-finite value.
  bool WriteCompensation(std::span<const double> correction_um) override;

  // hw::TemperatureSource
  std::size_t ChannelCount() const override { return sensors_.size(); }
  std::string ChannelName(std::size_t channel) const override;
  bool Read(std::span<hw::RawTemperature> out) override;
  hw::MeasuringRange ChannelMeasuringRange(std::size_t channel) const override;

 private:
  struct Axis;
  void ThermalStep(double dt_s);
  void IdleCoarse(double duration_s);
  void AdvanceMotion(double dt_s);
  double MotorMm(const Axis& a) const;
  void UpdatePlay(Axis& a);

  MachineDescription d_;
  std::uint64_t seed_;
  std::mt19937_64 rng_;
  double start_unix_s_ = 0;
  double t_s_ = 0;
  double step_s_ = 1;
  double next_grid_s_ = 0;   // next thermal step time
  double last_grid_s_ = 0;
  AmbientProfile ambient_;
  ThermalNetwork net_;
  std::size_t ambient_node_ = 0, coolant_node_ = 0, bed_node_ = 0;
  std::vector<std::unique_ptr<Axis>> axes_;
  std::vector<std::unique_ptr<VirtualSensor>> sensors_;
  std::vector<std::size_t> sensor_node_;
  struct ScheduledFault {
    std::size_t sensor;
    SensorFault fault;
    double at_s;
  };
  std::vector<ScheduledFault> scheduled_faults_;
  CoolantState coolant_ = CoolantState::kOff;
  bool compensation_enabled_ = true;
  bool link_fault_ = false;
  bool feed_hold_ = false;
  double log_interval_s_ = 0, next_log_s_ = 0;
  std::function<void(const VirtualMachine&)> logger_;
  double control_interval_s_ = 0, next_control_s_ = 0;
  std::function<void(VirtualMachine&)> controller_;
};

}  // namespace trueaxis::sim
