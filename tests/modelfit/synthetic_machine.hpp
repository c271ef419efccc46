#pragma once
// A known composite model that writes measurement files, so the fitter can be
// checked against the truth it should recover (degree, gains, sensors, Px, ρ).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/fit_options.hpp"
#include "trueaxis/modelfit/model_fit.hpp"

namespace trueaxis::model::testing {

struct SyntheticMachine {
  // Er(x) of each direction: cubic in u = (x − 250)/250 on 0 … 500 mm.
  std::vector<double> fwd_coef{1.0, 6.0, -2.0, 3.0};
  std::vector<double> rev_coef{4.0, 6.5, -2.0, 3.0};  // ~3 µm reversal
  double center_mm = 250, half_span_mm = 250;
  double px_mm = 0;                   // fixed end of the screw
  double k_nut = -0.006;              // µm per mm per °C (rise above ambient)
  double k_bearing = -0.002;
  double k_nut_flood_factor = 0.5;    // coolant flood halves the gains
  double rho = -0.0115;               // µm per mm per °C of room change
  double noise_um = 0.1;              // run-to-run scatter
  int runs = 5;
  double step_mm = 25;
  double travel_mm = 500;
  double baseline_c = 20.0;
  unsigned seed = 7;

  double Geometric(double x, bool forward) const {
    const auto& c = forward ? fwd_coef : rev_coef;
    const double u = (x - center_mm) / half_span_mm;
    double acc = 0;
    for (auto it = c.rbegin(); it != c.rend(); ++it) acc = acc * u + *it;
    return acc;
  }

  // One state: rises above ambient of nut / bearing, a motor sensor unrelated to
  // the error, the room's change, and the coolant.
  struct State {
    std::string label;
    double nut_rise, bearing_rise, motor_rise, ambient_rise;
    std::string coolant = "off";
  };

  measure::Measurement Make(const State& s, std::mt19937& rng, bool with_motor = true, bool with_temps = true) const {
    std::normal_distribution<double> noise(0, noise_um);
    std::normal_distribution<double> tnoise(0, 0.02);
    measure::Measurement m;
    m.source = s.label + ".csv";
    m.metadata = {{"axis", "X"}, {"state", s.label}};
    if (s.coolant != "off") m.metadata.push_back({"coolant", s.coolant});
    if (with_temps) {
      m.sensor_names = {"nut", "bearing"};
      if (with_motor) m.sensor_names.push_back("motor");
      m.sensor_names.push_back("ambient");
    }
    const double gain = s.coolant == "flood" ? k_nut_flood_factor : 1.0;
    const double tan_beta = gain * (k_nut * s.nut_rise + k_bearing * s.bearing_rise);
    int line = 2;
    for (int run = 1; run <= runs; ++run)
      for (int d = 0; d < 2; ++d) {
        const int n = static_cast<int>(travel_mm / step_mm);
        for (int i = 0; i <= n; ++i) {
          const int ii = d == 0 ? i : n - i;
          const double x = ii * step_mm;
          measure::MeasurementPoint p;
          p.run = run;
          p.direction = d == 0 ? Direction::kForward : Direction::kReverse;
          p.target_mm = x;
          p.deviation_um = Geometric(x, d == 0) + tan_beta * (px_mm - x) + rho * s.ambient_rise * (px_mm - x) +
                           noise(rng);
          p.source_line = ++line;
          if (with_temps) {
            const double amb = baseline_c + s.ambient_rise;
            p.temperatures_c = {amb + s.nut_rise + tnoise(rng), amb + s.bearing_rise + tnoise(rng)};
            if (with_motor) p.temperatures_c.push_back(amb + s.motor_rise + tnoise(rng));
            p.temperatures_c.push_back(amb + tnoise(rng));
          }
          m.points.push_back(p);
        }
      }
    return m;
  }

  std::vector<State> DefaultStates() const {
    return {{"cold", 0, 0, 0, 0},
            {"heated-1", 1.5, 0.5, 4.0, 0},
            {"heated-2", 3.0, 1.6, 1.0, 0},
            {"heated-3", 4.5, 1.5, 6.5, 0},
            {"heated-4", 6.0, 3.0, 2.5, 0},
            {"ambient-24", 0, 0, 0, 4.0}};
  }

  std::vector<FitState> MakeStates(const std::vector<State>& states) const {
    std::mt19937 rng(seed);
    std::vector<FitState> out;
    for (const auto& s : states) out.push_back(MakeFitState(Make(s, rng)));
    return out;
  }
};

// States whose nut temperature moves DURING the measurement (the thermal-lag and coolant-memory
// tests): one file per profile, 4 bidirectional runs over 0…500 mm every 50 mm, a point every
// dt_s, nut = start + slope·t (+ step after 200 s). The deviation is 2 + 0.004·x µm plus
// `thermal_um(profile, nut_c, x_mm, first)` (called in time order; `first` at each file's start,
// so a stateful truth can restart) plus noise.
struct TimedProfile {
  std::string label;
  std::string coolant = "off";
  double start_c = 20, slope_c_per_s = 0, step_c = 0;
};

template <typename Thermal>
std::vector<FitState> MakeTimedStates(const std::vector<TimedProfile>& profiles, double dt_s, double noise_um,
                                      unsigned seed, Thermal thermal_um) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, noise_um);
  std::vector<FitState> out;
  for (const auto& pr : profiles) {
    measure::Measurement m;
    m.source = pr.label + ".csv";
    m.metadata = {{"axis", "X"}, {"state", pr.label}, {"coolant", pr.coolant}};
    m.sensor_names = {"nut"};
    double t = 0;
    int line = 1;
    for (int run = 1; run <= 4; ++run)
      for (int d = 0; d < 2; ++d)
        for (int i = 0; i <= 10; ++i, t += dt_s) {
          const double x = (d == 0 ? i : 10 - i) * 50.0;
          const double nut = pr.start_c + pr.slope_c_per_s * t + (t > 200 ? pr.step_c : 0.0);
          measure::MeasurementPoint p;
          p.run = run;
          p.direction = d == 0 ? Direction::kForward : Direction::kReverse;
          p.target_mm = x;
          p.time_s = t;
          p.temperatures_c = {nut};
          p.deviation_um = 2.0 + 0.004 * x + thermal_um(pr, nut, x, t == 0) + noise(rng);
          p.source_line = ++line;
          m.points.push_back(p);
        }
    out.push_back(MakeFitState(m));
  }
  return out;
}

// Fit options for the timed states: a polynomial Er(x), the nut forced as key, Px = 0, no
// ambient sensor, a lag grid around the tests' true τ.
inline FitOptions TimedFitOptions() {
  FitOptions o;
  o.geometric = FitOptions::Geometric::kPolynomial;
  o.key_sensors = {"nut"};
  o.reference_position_mm = 0;
  o.ambient_sensor = "none";
  o.key_lag_grid_s = {0, 150, 300, 600, 1200, 2400};
  return o;
}

// A hand-made one-key axis "X": key "nut" and room "ambient", both with baseline 20 °C, Px 0,
// Er(x) = 0 and one coolant-off gains entry k (µm per mm per °C); tests set what they need on top.
inline AxisModel OneKeyAxis(double k_um_per_mm_per_c) {
  AxisModel a;
  a.axis = "X";
  a.reference_position_mm = 0;
  a.key_sensors = {"nut"};
  a.baseline_temp_c = {20};
  a.ambient_sensor = "ambient";
  a.ambient_baseline_c = 20;
  for (auto& d : a.directions) {
    d.geometric.coefficients_um = {0};
    ThermalGains g;
    g.k_um_per_mm_per_c = {k_um_per_mm_per_c};
    d.thermal.push_back(g);
  }
  return a;
}

// A fresh temporary directory `trueaxis_<name>_<pid>` with one warm measurement of axis X, m.csv
// (nut at `nut_c` at 0 and 100 s), and a manifest that starts it at 10000 s on the clock of
// temperature_log.csv, which the caller writes.
inline std::filesystem::path OneFileCampaignDir(const std::string& name, const std::string& nut_c) {
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  WriteTextFile((dir / "m.csv").string(), "# axis: X\n# state: warm\nrun,direction,target_mm,deviation_um,time_s,t_nut_c\n"
                                          "1,+,0,0,0," + nut_c + "\n1,+,100,0,100," + nut_c + "\n");
  WriteTextFile((dir / "manifest.json").string(),
                R"({"temperature_log": "temperature_log.csv", "measurements": [{"file": "m.csv", "axis": "X", "state": "warm", "start_time_s": 10000}]})");
  return dir;
}

// RMS of measured − predicted over every point of a state (the model's own thermal state along it).
inline double ResidualRms(const AxisModel& a, const FitState& s) {
  const auto res = PredictionResidual(a, s.measurement, s.coolant);
  double ss = 0;
  for (const auto& p : res.points) ss += p.deviation_um * p.deviation_um;
  return std::sqrt(ss / static_cast<double>(res.points.size()));
}

}  // namespace trueaxis::model::testing
