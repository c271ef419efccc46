#pragma once
// MachineDescription: everything the virtual machine tool needs to know about
// one machine, read from a TOML machine file (docs/machine-file.md).
//
// Units are in the names. Positions are machine coordinates in mm, 0 at the
// low end of travel. "Build" randomness (the random part of the pitch error,
// sensor offsets and gain errors) comes from `serial_seed`: it is a property
// of the machine, not of a run, so two runs with different run seeds measure
// the same machine with different noise.
#include <cstdint>
#include <limits>
#include <string_view>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"

namespace trueaxis::sim {

// Which end of travel carries the screw's fixed (thrust) bearing; the screw
// floats at the other end and grows away from the fixed end (seed 000).
enum class FixedEnd { kMin, kMax };

// Pitch error of the screw at 20 °C, as a function of machine position
// (seed 002): progressive + periodic harmonics of the lead + random part.
struct PitchErrorDescription {
  double progressive_um = -12;   // cumulative lead deviation over the whole travel (the linear part)
  double curvature_um = 3;       // bow: deviation of the mid-travel point from the chord
  std::vector<double> lead_harmonics_um = {1.2, 0.4};  // amplitude of harmonic k of the lead (period lead/k)
  double random_um = 2.5;        // rms of the smooth random part (build randomness)
  double random_wavelength_mm = 80;  // typical wavelength of the random part
  double flank_difference_um = 1.0;  // rms of the direction-dependent part (thread flanks), forward − reverse
};

// Lumped thermal parameters of one feed drive. Heat rates are given at
// `reference_feed_mm_min` and scale with (feed / reference)^heat_speed_exponent.
struct DriveThermalDescription {
  double reference_feed_mm_min = 3000;
  double heat_speed_exponent = 1.0;
  double nut_heat_w = 24;              // nut friction (preload, balls) at the reference feed
  double fixed_bearing_heat_w = 9;     // angular-contact pair at the fixed end
  double floating_bearing_heat_w = 4;  // support bearing at the floating end
  double motor_heat_w = 30;            // motor copper/iron losses at the reference feed
  double motor_idle_heat_w = 4;        // holding current at standstill
  double screw_convection_w_per_m2_k = 8;   // screw surface to still air (under the covers)
  double screw_convection_rotating_w_per_m2_k = 10;  // extra at the reference feed (a spinning screw
                                                     //   stirs the air), scales with (feed/reference)^0.6
  double nut_capacity_j_per_k = 6000;       // nut, nut housing and the saddle around it
  double nut_to_screw_w_per_k = 3.0;        // through the balls, into the screw under the nut
  double nut_to_ambient_w_per_k = 1.5;      // nut housing to table and air
  double bearing_capacity_j_per_k = 2500;   // each bearing seat
  double bearing_to_screw_w_per_k = 2.0;
  double bearing_to_bed_w_per_k = 1.5;
  double bearing_to_ambient_w_per_k = 0.6;
  double motor_capacity_j_per_k = 4000;
  double motor_to_ambient_w_per_k = 1.8;
  double motor_to_bearing_w_per_k = 0.6;    // through flange and coupling into the fixed-end seat
  int screw_segments = 24;                  // lumped segments along the screw
  double nut_length_mm = 100;               // the nut touches the screw over this length
};

struct AxisDescription {
  std::string name;                 // "X", "Y", "Z" (upper case)
  double travel_mm = 500;
  double lead_mm = 10;
  FixedEnd fixed_end = FixedEnd::kMin;
  double reference_mm = 0;          // reference point (home); defaults to the fixed-end side
  double screw_diameter_mm = 40;
  double screw_overhang_mm = 120;   // screw length beyond the travel (nut length, bearings)
  double screw_cte_um_per_m_c = 11.5;
  double backlash_um = 4;           // lost motion on reversal (reversal value B of ISO 230-2)
  double homing_repeatability_um = 0.5;  // 1 sigma of the reference position after homing (switch + encoder index)
  // Home switch (sim/homing.hpp): 1 sigma scatter of its trip point, and the nominal distance from
  // the trip point to the next motor index mark in the homing direction (NaN: half a lead).
  double home_switch_scatter_um = 20;
  double home_switch_to_index_mm = std::numeric_limits<double>::quiet_NaN();
  double bed_anchor_mm = 0;         // distance fixed bearing → bed's thermal anchor (levelling centre); the bed's growth over it shifts the whole axis
  PitchErrorDescription pitch;
  DriveThermalDescription thermal;
};

// Ambient temperature: mean + seasonal + daily cosine + a slow random
// "weather" part (run-seeded), °C.
struct AmbientDescription {
  double mean_c = 20.5;
  double seasonal_amplitude_c = 3.5;
  double seasonal_peak_day = 200;   // day of year of the warmest day
  double daily_amplitude_c = 1.2;
  double daily_peak_hour = 15;
  double weather_amplitude_c = 0.6; // rms of the multi-day random part
};

// Heat removal of one coolant state: extra conductance from the nut and the
// screw surface to the coolant, which sits at ambient + temperature_offset_c.
struct CoolantDescription {
  double nut_w_per_k = 0;
  double screw_w_per_m2_k = 0;
  double temperature_offset_c = 0;
};

struct BedDescription {
  double capacity_j_per_k = 1.6e6;   // cast-iron bed and column
  double to_ambient_w_per_k = 90;
  double cte_um_per_m_c = 10.5;
};

enum class SensorKind {
  kPt100Adc,    // Pt100 → isolated 0–50 °C / 0–5 V transmitter → 12-bit ADC (seed 000, PCI-1711)
  kDs18b20,     // digital, 0.0625 °C steps (seed 003)
  kRtdModule,   // Pt100 into an RTD input module (ADAM-6015 / ioLogik E1260), 16-bit
};

struct SensorDescription {
  std::string name;       // lower case: "x_nut", "ambient", ...
  SensorKind kind = SensorKind::kPt100Adc;
  std::string location;   // thermal node: "<axis>_nut", "<axis>_bearing", "<axis>_floating_bearing", "<axis>_motor", "bed", "ambient", "coolant"
  // Unset (NaN) → drawn from the kind's typical spread with serial_seed.
  double offset_c = std::numeric_limits<double>::quiet_NaN();
  double gain_error = std::numeric_limits<double>::quiet_NaN();  // reading = true·(1+gain_error)+offset
  double noise_c = std::numeric_limits<double>::quiet_NaN();     // rms, per sample
  double time_constant_s = std::numeric_limits<double>::quiet_NaN();  // first-order lag of probe + mounting
};

// A sensor fault the demo's working day injects (machine file `[[day_fault]]`; the zoo's "sensor
// that dies during the day", issue 10). The calibration campaign never sees it; the day's machine
// has it from `at_h` hours after the day's start (07:00) to the day's end (the other day, months
// later, starts with the sensor replaced).
struct DayFaultDescription {
  std::string sensor;          // a [[sensor]] name (or a default one: x_nut, ambient, ...)
  double at_h = 0;             // hours after the working day's start
  std::string kind = "open";   // open, short, stuck, drift, spikes (sim::ParseSensorFaultKind)
  int source_line = 0;         // for messages
};

struct MachineDescription {
  std::string source;       // file path (for messages)
  std::string name = "machine";
  std::uint64_t serial_seed = 1;
  std::string start_iso = "2026-03-02T07:00:00";  // simulated wall-clock time at t = 0 (UTC, no zone)
  double thermal_step_s = 1.0;   // integration step (reduced automatically if unstable)
  std::vector<AxisDescription> axes;
  AmbientDescription ambient;
  BedDescription bed;
  CoolantDescription coolant[kCoolantStateCount];  // by CoolantState
  std::vector<SensorDescription> sensors;  // defaults filled in by the reader
  std::vector<DayFaultDescription> day_faults;  // the working day's sensor faults (demo)

  // Index of an axis by name (case-insensitive), or -1.
  int AxisIndex(const std::string& name) const;
};

// Reads a machine file; throws InputError(file, line, key, why) on bad input.
MachineDescription ParseMachineToml(const std::string& text, const std::string& source);
MachineDescription ReadMachineFile(const std::string& path);

// Fills default sensors (<axis>_nut, <axis>_bearing, <axis>_motor, ambient,
// bed) when `sensors` is empty, and checks the description; throws
// InputError(source, message) when inconsistent.
void FinishMachineDescription(MachineDescription& m);

std::string_view SensorKindName(SensorKind k);

// A sensor name as every machine file takes it (the log's t_<name>_c column): 1–40 lower case
// letters, digits and '_', starting with a letter.
bool ValidSensorName(const std::string& name);

}  // namespace trueaxis::sim
