#pragma once
// LaserInterferometer: a virtual linear-displacement laser measuring one axis
// of a VirtualMachine the way seed 000 §2 and ISO 230-2 describe:
// bidirectional linear test cycle, 3–5 runs, targets every ~20–25 mm, an
// overrun beyond each end for the reversal, a stop and averaged reading at
// each target. The test takes machine time: the machine keeps heating or
// cooling while it runs, and every sensor is recorded at every point.
//
// What the laser sees: the table's displacement from where the laser was
// zeroed (Setup), in units of the air-compensated wavelength — i.e. a true
// length (20 °C scale) apart from the residual error of its air sensor.
// With material compensation on, it rescales the reading to a part of CTE
// `material_cte_um_per_m_c` at the temperature of its material sensor
// (placed on the table: the "bed" node), as a real laser does. Off (default),
// a uniform ambient change ΔT gives ΔEr = α_screw·ΔT·(distance from the fixed
// end); on, the difference (α_screw − α_material) remains.
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <functional>
#include <string>

#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

struct LaserOptions {
  int runs = 5;                    // ISO 230-2: 5 (seed 000: 3–5)
  double spacing_mm = 25;          // nominal target spacing (adjusted to fill the range evenly)
  double first_mm = std::numeric_limits<double>::quiet_NaN();  // default: overrun_mm
  double last_mm = std::numeric_limits<double>::quiet_NaN();   // default: travel − overrun_mm
  double overrun_mm = 5;
  double feed_mm_min = 2000;
  double dwell_s = 3;              // settle + averaging time at each target
  double resolution_nm = 1;
  double noise_nm = 150;           // rms of one averaged reading (vibration, air turbulence)
  bool material_compensation = false;
  double material_cte_um_per_m_c = 11.5;
  double material_sensor_error_c = 0.1;  // rms, drawn once per instrument
  double air_sensor_error_c = 0.1;       // rms, drawn once per instrument (≈0.93 ppm/°C)

  bool IsValid(std::string* why) const;
};

class LaserInterferometer {
 public:
  LaserInterferometer(LaserOptions options, std::uint64_t seed);
  const LaserOptions& options() const { return o_; }

  // Moves the axis to datum_mm (approaching forward) and zeroes the laser there.
  void Setup(VirtualMachine& vm, std::size_t axis, double datum_mm);
  // One averaged reading of the axis position, mm (needs Setup on that axis).
  double ReadMm(VirtualMachine& vm);
  // A measurement of the set-up axis with the instrument's and the machine's
  // metadata (axis, machine, date, seed, instrument, travel, lead, cte, fixed
  // end, reference, laser zero, coolant) and the sensor columns; no points yet.
  measure::Measurement StartMeasurement(const VirtualMachine& vm) const;
  // One reading at `target_mm` where the axis stands now: deviation (1 nm),
  // time since t0_s (0.1 s) and every sensor (NaN when the hardware flags it).
  measure::MeasurementPoint Reading(VirtualMachine& vm, int run, Direction direction, double target_mm, double t0_s);
  // Target positions for the axis (ascending).
  std::vector<double> Targets(const VirtualMachine& vm, std::size_t axis) const;
  // Runs the full bidirectional test; metadata: axis, machine, date, seed,
  // lead, cte, fixed end, laser settings plus `extra_metadata`.
  measure::Measurement Measure(VirtualMachine& vm,
                               const std::vector<std::pair<std::string, std::string>>& extra_metadata = {}) {
    return Measure(vm, o_.runs, extra_metadata);
  }
  // Same with another number of runs.
  measure::Measurement Measure(VirtualMachine& vm, int runs,
                               const std::vector<std::pair<std::string, std::string>>& extra_metadata);

 private:
  LaserOptions o_;
  std::mt19937_64 rng_;
  double air_error_c_ = 0, material_error_c_ = 0;
  int axis_ = -1;
  double zero_actual_mm_ = 0, zero_commanded_mm_ = 0;
};

// The bidirectional test cycle of ISO 230-2 / seed 000 §5, the one copy every laser test runs:
// per run, approach the first target from below by `overrun_mm` and record every target going up,
// then overrun the last and record every target coming down. `move_to(position_mm)` brings the
// axis there (however the caller moves it: directly, through its interpolator, or with a
// compensator cycling); `record(run, direction, target_mm)` moves to the target, dwells and reads.
void RunBidirectionalCycle(const std::vector<double>& targets, int runs, double overrun_mm,
                           const std::function<void(double)>& move_to,
                           const std::function<void(int, Direction, double)>& record);

}  // namespace trueaxis::sim
