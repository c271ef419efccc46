#pragma once
// Identification of the tracking-error model from axis tests (docs/fiveaxis.md,
// "Identification"): each axis alone runs a sine test — A·(1 − cos 2πft) for a
// few whole periods at several frequencies, amplitude within the axis's
// velocity limit — once without feed-forward and once with kf = 1, as a
// commissioning engineer records them with the drive's trace. The model's
// coefficients are the least-squares fit of the measured tracking error
// (command − measured position) to the command's velocity, acceleration and
// jerk. Only the traces are used, never the drive's parameters.
#include <functional>
#include <vector>

#include "trueaxis/fiveaxis/machine.hpp"
#include "trueaxis/fiveaxis/tracking_model.hpp"

namespace trueaxis::fiveaxis {

struct AxisTestOptions {
  // Well below the position-loop bandwidth, where the model (a low-frequency
  // expansion) holds and where tool paths live.
  std::vector<double> frequencies_hz = {0.25, 0.5, 1, 2, 3};
  int periods = 2;
  double velocity_fraction = 0.5;   // peak velocity / the axis's velocity limit
  double max_acceleration = 2000;   // mm/s² or deg/s²
  double max_amplitude = 50;        // mm or deg
  double rest_s = 0.1;              // standing between frequencies
  // A slow test with gentle reversals (where friction turns over slowly):
  // this frequency at this peak velocity (mm/s or deg/s).
  double slow_frequency_hz = 0.25;
  double slow_peak_velocity = 1.0;
  std::vector<double> friction_bands = {0.01, 0.03, 0.1, 0.3, 1, 3};  // candidates, mm/s or deg/s
  int friction_band_refinements = 8;  // golden-section steps between the best candidate's neighbours
  // Drive mode (tracking_model.hpp): searched from a grid of frequencies (this lowest one, each next
  // mode_grid_ratio higher, up to the servo rate / 8) and dampings, then refined; kept when it lowers
  // the feed-forward run's residual by at least mode_min_gain (a share of it).
  bool search_mode = true;
  double mode_min_hz = 2;
  double mode_grid_ratio = 1.4;
  std::vector<double> mode_dampings = {0.05, 0.1, 0.2, 0.35, 0.6, 1.0};
  double mode_min_gain = 0.25;
  double derivative_window_s = 0.01;
  bool with_extensions = true;
};

// The test command of one axis (one sample per servo period).
std::vector<double> AxisTestCommand(const DriveParams& d, double servo_rate_hz, const AxisTestOptions& o);

// A recorded axis test: command and measured position.
struct AxisTrace {
  std::vector<double> command, measured;
};
// Fits one axis's coefficients from a trace.
// with_extensions = false fits the seed's three terms only; `mode` (when present) adds its terms.
ModelCoefficients FitTrackingCoefficients(const AxisTrace& trace, double dt_s, double window_s, bool with_extensions,
                                          double friction_band, const DriveMode& mode, double* fit_rms,
                                          double* signal_rms);
// The drive mode that explains a trace best (grid, then refined; AxisTestOptions), or none when it
// lowers the residual of the model without a mode by less than o.mode_min_gain.
DriveMode FindDriveMode(const AxisTrace& trace, double dt_s, double friction_band, const AxisTestOptions& o);

// Runs the tests on the virtual machine's drives (any `run` — e.g. a real
// machine's trace recorder — may be passed instead) and fits the model.
using AxisTestRunner = std::function<std::vector<double>(int axis, double kf, const std::vector<double>& command)>;
TrackingErrorModel IdentifyTrackingModel(const FiveAxisMachine& m, const AxisTestOptions& o, const AxisTestRunner& run);
// The runner that drives the virtual machine's servo drives.
AxisTestRunner VirtualMachineRunner(const FiveAxisMachine& m);

}  // namespace trueaxis::fiveaxis
