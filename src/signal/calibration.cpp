#include "trueaxis/signal/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::signal {

bool CalibrationOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (min_points < 2) return fail("min_points must be >= 2");
  if (!(min_span_c > 0)) return fail("min_span_c must be > 0");
  if (!(min_gain > 0 && max_gain > min_gain)) return fail("need 0 < min_gain < max_gain");
  return true;
}

std::string CalibrationFit::BriefReport() const {
  return fmt::format("gain {:.5f}{} offset {:+.3f} °C from {} points, reference span {:.2f} °C; residual rms {:.3f} °C, "
                     "max {:.3f} °C (before: max {:.3f} °C)",
                     calibration.gain, gain_fitted ? "" : " (not fitted: reference span too small)",
                     calibration.offset_c,
                     points, reference_span_c, rms_residual_c, max_abs_residual_c, max_abs_error_before_c);
}

CalibrationFit FitCalibration(std::span<const double> sensor_c, std::span<const double> reference_c,
                              const CalibrationOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("calibration options: " + why);
  if (sensor_c.size() != reference_c.size())
    throw std::invalid_argument(fmt::format("sensor has {} readings, reference {}", sensor_c.size(), reference_c.size()));
  // Centred sums: numerically safe at room temperature (x ≈ 20..40 °C).
  double sx = 0, sy = 0;
  int n = 0;
  double ymin = INFINITY, ymax = -INFINITY;
  for (std::size_t i = 0; i < sensor_c.size(); ++i) {
    if (!std::isfinite(sensor_c[i]) || !std::isfinite(reference_c[i])) continue;
    sx += sensor_c[i];
    sy += reference_c[i];
    ymin = std::min(ymin, reference_c[i]);
    ymax = std::max(ymax, reference_c[i]);
    ++n;
  }
  if (n < options.min_points)
    throw std::invalid_argument(fmt::format("only {} simultaneous readings, need at least {}", n, options.min_points));
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < sensor_c.size(); ++i) {
    if (!std::isfinite(sensor_c[i]) || !std::isfinite(reference_c[i])) continue;
    sxx += (sensor_c[i] - mx) * (sensor_c[i] - mx);
    sxy += (sensor_c[i] - mx) * (reference_c[i] - my);
  }
  CalibrationFit fit;
  fit.points = n;
  fit.reference_span_c = ymax - ymin;
  if (fit.reference_span_c >= options.min_span_c && sxx > 0) {
    fit.calibration.gain = sxy / sxx;
    fit.gain_fitted = true;
    if (!(fit.calibration.gain >= options.min_gain && fit.calibration.gain <= options.max_gain))
      throw std::invalid_argument(fmt::format(
          "fitted scale factor {:.4f} is outside the plausible band [{}, {}]: check wiring, sensor type and scaling",
          fit.calibration.gain, options.min_gain, options.max_gain));
  }
  fit.calibration.offset_c = my - fit.calibration.gain * mx;
  double ss = 0;
  for (std::size_t i = 0; i < sensor_c.size(); ++i) {
    if (!std::isfinite(sensor_c[i]) || !std::isfinite(reference_c[i])) continue;
    const double e = fit.calibration.Apply(sensor_c[i]) - reference_c[i];
    ss += e * e;
    fit.max_abs_residual_c = std::max(fit.max_abs_residual_c, std::abs(e));
    fit.max_abs_error_before_c = std::max(fit.max_abs_error_before_c, std::abs(sensor_c[i] - reference_c[i]));
  }
  fit.rms_residual_c = std::sqrt(ss / n);
  return fit;
}

std::string CalibrationSet::FullReport() const {
  std::string out = fmt::format("calibration against reference '{}'{}\n", reference,
                                session.empty() ? "" : " (session " + session + ")");
  for (const auto& [name, fit] : sensors) out += fmt::format("  {:<16} {}\n", name, fit.BriefReport());
  return out;
}

namespace {

// max − min of the sensor and of the reference over the rows where both were read.
std::pair<double, double> SpansOverSharedRows(const std::vector<double>& sensor_c, const std::vector<double>& reference_c) {
  double smin = INFINITY, smax = -INFINITY, rmin = INFINITY, rmax = -INFINITY;
  for (std::size_t i = 0; i < sensor_c.size() && i < reference_c.size(); ++i) {
    if (!std::isfinite(sensor_c[i]) || !std::isfinite(reference_c[i])) continue;
    smin = std::min(smin, sensor_c[i]);
    smax = std::max(smax, sensor_c[i]);
    rmin = std::min(rmin, reference_c[i]);
    rmax = std::max(rmax, reference_c[i]);
  }
  if (smin > smax) return {0.0, 0.0};
  return {smax - smin, rmax - rmin};
}

// In a session every sensor sits at the reference's temperature, so their spans agree (a gain in
// [min_gain, max_gain]). One that stays put while the other moves by min_span_c or more was not at the
// other's temperature — stuck, unplugged, out of the block — and an offset-only fit of it would be
// meaningless (a constant sensor against a reference over 23 °C gave offset +13 °C, residual 6 °C).
// Refused, naming the column that did not move.
void RefuseSpanMismatch(const CalibrationSession& session, const std::string& sensor, const std::vector<double>& sensor_c,
                        const std::string& reference, const std::vector<double>& reference_c,
                        const CalibrationOptions& options) {
  const auto [sensor_span, reference_span] = SpansOverSharedRows(sensor_c, reference_c);
  const double larger = std::max(sensor_span, reference_span);
  if (larger < options.min_span_c || std::min(sensor_span, reference_span) >= 0.5 * larger) return;
  const bool sensor_still = sensor_span < reference_span;
  throw InputError(session.source, 0, sensor_still ? sensor : reference,
                   fmt::format("cannot calibrate '{}': {} '{}' spans {:.2f} °C while {} '{}' spans {:.2f} °C over the "
                               "same rows; a stuck or disconnected sensor, or one not at the other's temperature",
                               sensor, sensor_still ? "sensor" : "reference", sensor_still ? sensor : reference,
                               sensor_still ? sensor_span : reference_span, sensor_still ? "reference" : "sensor",
                               sensor_still ? reference : sensor, sensor_still ? reference_span : sensor_span));
}

// Header names may carry the measurement-CSV style "t_<name>_c".
std::string SensorNameFromHeader(std::string_view h) {
  std::string name(h);
  if (name.size() > 4 && name.rfind("t_", 0) == 0 && name.substr(name.size() - 2) == "_c")
    name = name.substr(2, name.size() - 4);
  return name;
}

}  // namespace

CalibrationSession ParseCalibrationSessionCsv(std::string_view text, const std::string& source) {
  CalibrationSession s;
  s.source = source;
  std::vector<int> column_to_sensor;  // -1: ignored column (time_s)
  bool have_header = false;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  int line_no = 0;
  while (cursor.Next()) {
    line_no = cursor.number();
    const std::string_view line = cursor.line();
    if (line.empty() || line.front() == '#') continue;
    auto fields = SplitCsvFields(line);
    if (!have_header) {
      have_header = true;
      RefuseEmptyHeaderField(fields, source, line_no);
      for (auto f : fields) {
        if (f == "time_s" || f == "time") {
          column_to_sensor.push_back(-1);
          continue;
        }
        std::string name = SensorNameFromHeader(f);
        if (std::find(s.sensors.begin(), s.sensors.end(), name) != s.sensors.end())
          throw InputError(source, line_no, name, "column given twice");
        column_to_sensor.push_back(static_cast<int>(s.sensors.size()));
        s.sensors.push_back(name);
      }
      if (s.sensors.size() < 2)
        throw InputError(source, line_no, "header", "need the reference and at least one sensor column");
      s.readings_c.assign(s.sensors.size(), {});
      continue;
    }
    if (fields.size() != column_to_sensor.size())
      throw InputError(source, line_no, "", fmt::format("{} fields, the header has {}", fields.size(), column_to_sensor.size()));
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (column_to_sensor[c] < 0) continue;
      auto& column = s.readings_c[static_cast<std::size_t>(column_to_sensor[c])];
      if (fields[c].empty()) {
        column.push_back(NAN);
        continue;
      }
      auto v = ParseDouble(fields[c]);
      if (!v || !std::isfinite(*v))
        throw InputError(source, line_no, s.sensors[static_cast<std::size_t>(column_to_sensor[c])],
                         fmt::format("'{}' is not a temperature in °C", fields[c]));
      if (*v < -100 || *v > 300)
        throw InputError(source, line_no, s.sensors[static_cast<std::size_t>(column_to_sensor[c])],
                         fmt::format("{} °C is not a plausible calibration temperature", fields[c]));
      column.push_back(*v);
    }
  }
  if (!have_header) throw InputError(source, "empty calibration session: no header row");
  if (s.rows() == 0) throw InputError(source, "calibration session has a header but no readings");
  return s;
}

CalibrationSession ReadCalibrationSessionCsv(const std::string& path) {
  return ParseCalibrationSessionCsv(ReadTextFile(path), path);
}

CalibrationSet CalibrateSession(const CalibrationSession& session, const std::string& reference,
                                const CalibrationOptions& options) {
  auto it = std::find(session.sensors.begin(), session.sensors.end(), reference);
  if (it == session.sensors.end()) {
    std::string names;
    for (const auto& n : session.sensors) names += (names.empty() ? "" : ", ") + n;
    throw InputError(session.source, 0, "reference",
                     fmt::format("no column '{}' in the session (columns: {})", reference, names));
  }
  const auto& ref = session.readings_c[static_cast<std::size_t>(it - session.sensors.begin())];
  CalibrationSet set;
  set.reference = reference;
  set.session = session.source;
  for (std::size_t i = 0; i < session.sensors.size(); ++i) {
    if (session.sensors[i] == reference) continue;
    RefuseSpanMismatch(session, session.sensors[i], session.readings_c[i], reference, ref, options);
    try {
      set.sensors[session.sensors[i]] = FitCalibration(session.readings_c[i], ref, options);
    } catch (const std::invalid_argument& e) {
      throw InputError(session.source, 0, session.sensors[i], std::string("cannot calibrate: ") + e.what());
    }
  }
  return set;
}

std::string CalibrationSetToJson(const CalibrationSet& set) {
  nlohmann::ordered_json j;
  j["format"] = "trueaxis-calibration";
  j["version"] = 1;
  j["reference"] = set.reference;
  j["session"] = set.session;
  j["formula"] = "corrected_c = gain * raw_c + offset_c";
  nlohmann::ordered_json sensors = nlohmann::ordered_json::object();
  for (const auto& [name, fit] : set.sensors) {
    sensors[name] = {{"gain", fit.calibration.gain},
                     {"offset_c", fit.calibration.offset_c},
                     {"gain_fitted", fit.gain_fitted},
                     {"points", fit.points},
                     {"reference_span_c", fit.reference_span_c},
                     {"rms_residual_c", fit.rms_residual_c},
                     {"max_abs_residual_c", fit.max_abs_residual_c},
                     {"max_abs_error_before_c", fit.max_abs_error_before_c}};
  }
  j["sensors"] = sensors;
  return j.dump(2) + "\n";
}

CalibrationSet CalibrationSetFromJson(std::string_view text, const std::string& source) {
  nlohmann::json j = ParseJsonOrThrow(text, source);
  if (!j.is_object() || j.value("format", "") != "trueaxis-calibration")
    throw InputError(source, 0, "format", "not a trueaxis calibration file (expected \"format\": \"trueaxis-calibration\")");
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int>() != 1)
    throw InputError(source, 0, "version", "unsupported calibration file version (this trueaxis reads version 1)");
  CalibrationSet set;
  set.reference = j.value("reference", "");
  set.session = j.value("session", "");
  if (!j.contains("sensors") || !j["sensors"].is_object()) throw InputError(source, 0, "sensors", "missing or not an object");
  for (const auto& [name, s] : j["sensors"].items()) {
    auto number = [&](const char* key, bool required, double fallback) {
      if (!s.contains(key)) {
        if (required) throw InputError(source, 0, "sensors." + name + "." + key, "missing");
        return fallback;
      }
      if (!s[key].is_number()) throw InputError(source, 0, "sensors." + name + "." + key, "not a number");
      const double v = s[key].get<double>();
      if (!std::isfinite(v)) throw InputError(source, 0, "sensors." + name + "." + key, "not finite");
      return v;
    };
    CalibrationFit fit;
    fit.calibration.gain = number("gain", true, 1);
    fit.calibration.offset_c = number("offset_c", true, 0);
    if (!(fit.calibration.gain > 0)) throw InputError(source, 0, "sensors." + name + ".gain", "must be > 0");
    fit.gain_fitted = s.value("gain_fitted", true);
    fit.points = static_cast<int>(number("points", false, 0));
    fit.reference_span_c = number("reference_span_c", false, 0);
    fit.rms_residual_c = number("rms_residual_c", false, 0);
    fit.max_abs_residual_c = number("max_abs_residual_c", false, 0);
    fit.max_abs_error_before_c = number("max_abs_error_before_c", false, 0);
    set.sensors[name] = fit;
  }
  return set;
}

void WriteCalibrationFile(const std::string& path, const CalibrationSet& set) {
  WriteTextFile(path, CalibrationSetToJson(set));
}

CalibrationSet ReadCalibrationFile(const std::string& path) {
  return CalibrationSetFromJson(ReadTextFile(path), path);
}

}  // namespace trueaxis::signal
