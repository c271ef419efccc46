#pragma once
// Calibration of temperature sensors against a reference sensor (seed 000
// "自動標定": 零位校正 and 比例係數確定 — zero offset and scale factor).
//
// During a calibration session every sensor and the reference sensor sit at
// the same temperature (a block, a bath, or the machine soaked at several
// temperatures) and are read simultaneously. For each sensor we fit, by
// ordinary least squares over all simultaneous rows,
//
//     reference_c ≈ gain · sensor_c + offset_c
//
// and apply `corrected = gain · raw + offset` afterwards. A scale factor needs
// a spread of temperatures: below `min_span_c` the fit keeps gain = 1 and only
// fits the offset (and says so), instead of inventing a slope from noise.
#include <map>
#include <span>
#include <string>
#include <vector>

namespace trueaxis::signal {

struct SensorCalibration {
  double gain = 1.0;      // scale factor
  double offset_c = 0.0;  // zero offset
  double Apply(double raw_c) const { return gain * raw_c + offset_c; }
};

struct CalibrationOptions {
  int min_points = 3;
  double min_span_c = 2.0;      // reference span needed to fit the scale factor
  double min_gain = 0.8;        // a fitted gain outside [min_gain, max_gain] is rejected:
  double max_gain = 1.25;       // such a sensor is wired or scaled wrongly, not "calibrated"
  bool IsValid(std::string* why) const;
};

struct CalibrationFit {
  SensorCalibration calibration;
  bool gain_fitted = false;     // false: span too small, offset only
  int points = 0;
  double reference_span_c = 0;  // max - min of the reference over the used rows
  double rms_residual_c = 0;    // after calibration
  double max_abs_residual_c = 0;
  double max_abs_error_before_c = 0;  // |sensor - reference| before calibration
  std::string BriefReport() const;
};

// Throws std::invalid_argument when sizes differ, fewer than min_points
// finite pairs, or the fitted gain is outside the plausible band.
CalibrationFit FitCalibration(std::span<const double> sensor_c, std::span<const double> reference_c,
                              const CalibrationOptions& options = {});

// A calibration for a set of sensors, as stored in cal.json.
struct CalibrationSet {
  std::string reference;                          // name of the reference sensor
  std::string session;                            // where the session came from (file name)
  std::map<std::string, CalibrationFit> sensors;  // by sensor name; the reference itself is not listed
  std::string FullReport() const;
};

// Simultaneous readings of a calibration session: CSV with a header row of
// sensor names (an optional `time_s` column is ignored for fitting), `#`
// comment lines, one row per instant; an empty cell means "not read then".
struct CalibrationSession {
  std::string source;
  std::vector<std::string> sensors;
  std::vector<std::vector<double>> readings_c;  // [sensor][row], NaN where empty
  std::size_t rows() const { return readings_c.empty() ? 0 : readings_c.front().size(); }
};
CalibrationSession ParseCalibrationSessionCsv(std::string_view text, const std::string& source);
CalibrationSession ReadCalibrationSessionCsv(const std::string& path);

// Fits every sensor of the session against `reference`. Throws InputError
// (naming the file and the sensor) when the reference is missing or a sensor
// cannot be calibrated.
CalibrationSet CalibrateSession(const CalibrationSession& session, const std::string& reference,
                                const CalibrationOptions& options = {});

// JSON: {"format":"trueaxis-calibration","version":1,"reference":..,"session":..,
//        "sensors":{"x_nut":{"gain":..,"offset_c":..,"points":..,...}}}
std::string CalibrationSetToJson(const CalibrationSet& set);
CalibrationSet CalibrationSetFromJson(std::string_view text, const std::string& source);
void WriteCalibrationFile(const std::string& path, const CalibrationSet& set);
CalibrationSet ReadCalibrationFile(const std::string& path);

}  // namespace trueaxis::signal
