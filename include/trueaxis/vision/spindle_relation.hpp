#pragma once
// The marker-to-spindle relation, calibrated from a reference measurement (docs/vision.md,
// "The marker is not the whole spindle").
//
// Seed 001 reads the spindle's growth as Czb·(K − 1): the whole spindle strains like the marker.
// The marker sits on the nose segment; the part behind it (towards the fixed bearing, heated by
// the rear bearing and the motor) lags on heating and cooling and carries relatively more heat
// the faster the spindle turns (motor losses grow with the square of the speed, bearing losses
// with a lower power), so that reading misses more at higher speed.
//
// The relation here keeps the camera's reading M = Czb·(K − 1) as the input and adds what the
// marker cannot see, fitted once against a reference measurement of the real growth (a
// displacement probe or tool setter against a test bar, every few minutes over a day that
// heats and cools the spindle):
//
//   Δz = a·M + b·L_τ(M) + c·L_τ((n / n_ref)²)
//
// L_τ: first-order lag with time constant τ (a geometric grid 5 min … 8 h, least squares for
// a, b, c), n the spindle speed the controller reports, n_ref = 10 000 rpm. The relation knows
// the speeds it was calibrated on; beyond the highest it extrapolates and says so.
#include <string>
#include <vector>

namespace trueaxis::vision {

struct SpindleRelation {
  double marker_gain = 1;        // a
  double marker_lag_gain = 0;    // b
  double speed_lag_um = 0;       // c, µm per unit of (n / n_ref)², lagged
  double tau_s = 1800;
  double reference_rpm = 10000;
  double calibrated_rpm_max = 0;  // the highest speed of the calibration run
  double calibration_rms_um = 0;  // residual against the reference measurement
  int calibration_samples = 0;
};

struct SpindleRelationSample {
  double time_s = 0;
  double marker_um = 0;    // Czb·(K − 1) read by the camera
  double rpm = 0;          // spindle speed at that time
  double reference_um = 0; // the real growth, measured (calibration only)
};

// Needs ≥ 10 samples with increasing time over a run that holds two speeds or more for ≥ 3 samples each (std::invalid_argument
// otherwise, saying what is missing).
SpindleRelation FitSpindleRelation(const std::vector<SpindleRelationSample>& samples);

// Causal, one reading at a time (the lags start at the first sample's values).
class SpindleRelationPredictor {
 public:
  explicit SpindleRelationPredictor(const SpindleRelation& relation) : r_(relation) {}
  double Push(double time_s, double marker_um, double rpm);  // predicted growth Δz (µm)
  // True once a speed above the calibrated maximum (by more than 2 %) was seen.
  bool beyond_calibration() const { return beyond_; }

 private:
  SpindleRelation r_;
  bool started_ = false, beyond_ = false;
  double last_t_ = 0, lag_marker_ = 0, lag_speed_ = 0;
};

// "the spindle ran at 15000 rpm, above the 10000 rpm the marker-to-spindle relation was
// calibrated on: …" — empty when within.
std::string SpindleRelationSpeedWarning(const SpindleRelation& relation, double max_rpm_seen);

}  // namespace trueaxis::vision
