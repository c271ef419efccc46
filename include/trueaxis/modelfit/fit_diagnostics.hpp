#pragma once
// What the fit tells about its residual (docs/model-file.md, "What the fit tells you about its
// residual"): per measured state the residual that remains after the model, split along the
// travel into offset (mean), slope (linear trend, µm per metre and end to end over the travel)
// and the pattern left over (RMS); whether an offset or a slope is consistent across the states
// (the model then has a structure no mounted sensor follows) and where a sensor would help; and
// each key sensor's share of the thermal correction. A pure function of what the fit already has.
#include <limits>
#include <string>
#include <vector>

namespace trueaxis::model {

// One measured state: the residual (measured − model) at each point and, per key sensor, that
// sensor's part of the model's thermal correction at the same points ([key][point], µm).
struct StateResidualInput {
  std::string label;
  bool cold = false;  // a cold (reference) state: its residual is the geometric fit's, not judged for structure
  std::vector<double> position_mm;
  std::vector<double> residual_um;
  std::vector<std::vector<double>> key_contribution_um;
};

struct ResidualDiagnosisInput {
  std::vector<std::string> key_sensors;
  std::vector<StateResidualInput> states;
  bool cross_validated = false;  // residuals are held-out predictions (else in-sample)
  // The repeatability (µm) of the cold runs, NaN if unknown. An offset or end-to-end slope counts
  // when it exceeds the larger of it and two standard errors of the states' scatter.
  double noise_um = std::numeric_limits<double>::quiet_NaN();
};

struct StateResidualShape {
  std::string label;
  bool cold = false;
  std::size_t points = 0;
  double offset_um = 0;           // mean residual
  double slope_um_per_m = 0;      // linear trend along the travel
  double end_to_end_um = 0;       // the slope over the state's travel
  double pattern_rms_um = 0;      // what is left after offset and slope
  double residual_rms_um = 0;     // all of it
};

struct KeySensorShare {
  std::string sensor;
  double rms_um = 0;       // RMS of the sensor's correction over every point of every state
  double share_pct = 0;    // of the total (mean squares; the shares sum to 100 %)
};

struct ResidualDiagnosis {
  bool cross_validated = false;
  double offset_level_um = 0;  // an offset counts above this (noise level)
  double slope_level_um = 0;   // an end-to-end slope counts above this
  std::string noise_source;
  std::vector<StateResidualShape> states;
  std::vector<KeySensorShare> key_shares;
  bool slope_structure = false;   // a slope of the same sign above the noise in most judged states
  bool offset_structure = false;  // an offset above the noise in most judged states
  std::vector<std::string> findings;  // plain-words statements with the numbers, and the suggested sensor
};

ResidualDiagnosis DiagnoseResidual(const ResidualDiagnosisInput& in);

// A few lines for `fit`'s normal output; the per-state table for the full report.
std::string ResidualDiagnosisBrief(const ResidualDiagnosis& d);
std::string ResidualDiagnosisTable(const ResidualDiagnosis& d);

}  // namespace trueaxis::model
