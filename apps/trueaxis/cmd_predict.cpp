// trueaxis predict --model model.json --axis X --position-mm P --direction +
//                  [--temp nut=25.1,bearing=23.4] [--ambient-c T] [--coolant flood] [--json]
// trueaxis predict --model model.json --measurement FILE.csv [--coolant flood] [--residual-out R.csv]
//   (held-out check: every point predicted from its own temperatures; prints ISO 230-2 A
//    of the measured error and of measured − predicted, and writes the residual file)
// Prints the model's predicted error at one position and the correction the
// runtime would apply (docs/sign-convention.md: error = actual − commanded,
// correction = −error, added to the command).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "measurement_input.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::cli {
namespace {

struct PredictOptions {
  std::string model;
  std::string axis;
  double position_mm = 0;
  std::string direction;
  std::vector<std::string> temps;
  double ambient_c = std::numeric_limits<double>::quiet_NaN();
  double motion_m_per_min = std::numeric_limits<double>::quiet_NaN();  // the motion-heat input, when the model has one
  std::string coolant;  // empty: off (or the measurement file's own)
  bool geometric_only = false;
  bool json = false;
  std::string measurement;
  std::string residual_out;
  std::string temperature_log;  // with --measurement: history before the file, for the thermal lag
  bool position_given = false;
  MeasurementInputOptions input;
};

// `first` and the later fallbacks of `parent` that replace the same sensor and whose sensors
// `usable` accepts: the compensator averages them (AxisModel::replaces, docs/model-file.md).
template <typename Usable>
std::vector<const model::AxisModel*> FallbackGroup(const model::AxisModel& parent, const model::AxisModel& first,
                                                   Usable usable) {
  std::vector<const model::AxisModel*> group{&first};
  bool after = false;
  for (const auto& f : parent.fallbacks) {
    if (&f == &first) after = true;
    else if (after && !first.replaces.empty() && f.replaces == first.replaces && usable(f)) group.push_back(&f);
  }
  return group;
}

std::string DescribeFallbacks(const std::vector<const model::AxisModel*>& group) {
  if (group.size() == 1) return fmt::format("the fallback model fitted without it (keys {})", fmt::join(group[0]->key_sensors, ", "));
  std::vector<std::string> keys;
  for (const auto* f : group) keys.push_back(fmt::format("{}", fmt::join(f->key_sensors, " + ")));
  return fmt::format("the mean of the {} fallback models fitted without it (keys {})", group.size(), fmt::join(keys, "; "));
}

void RunPredictMeasurement(const PredictOptions& o, const model::CompositeModel& model) {
  const auto m = o.input.Read(o.measurement);
  std::string axis_name = o.axis.empty() ? std::string(Trim(m.Meta("axis").value_or(""))) : o.axis;
  if (axis_name.empty())
    throw InputError(o.measurement, 0, "axis", "no '# axis:' metadata line; pass --axis");
  const auto* axis = model.FindAxis(axis_name);
  if (!axis) throw InputError(o.model, 0, "--axis", fmt::format("the model has no axis '{}'", axis_name));
  // Coolant: the option if given, else the file's '# coolant:' line, else off.
  std::string coolant_name = o.coolant;
  if (coolant_name.empty()) coolant_name = std::string(Trim(m.Meta("coolant").value_or("off")));
  const auto coolant = ParseCoolantState(coolant_name);
  if (!coolant)
    throw InputError(o.measurement, o.coolant.empty() ? m.MetaLine("coolant") : 0, o.coolant.empty() ? "coolant" : "--coolant",
                     fmt::format("unknown coolant state '{}'", coolant_name));
  // A key sensor not in the file, or never read in it (a dead channel): the first fallback model
  // whose keys all are, as the compensator does when that sensor is lost; else refused.
  const auto read = [&](const std::string& k) {
    const auto idx = m.SensorIndex(k);
    if (!idx) return false;
    for (const auto& pt : m.points)
      if (std::isfinite(pt.temperatures_c[*idx])) return true;
    return false;
  };
  const auto all_read = [&](const model::AxisModel& a) {
    return std::all_of(a.key_sensors.begin(), a.key_sensors.end(), read) && (a.ambient_sensor.empty() || read(a.ambient_sensor));
  };
  std::string fallback_note;
  std::vector<const model::AxisModel*> averaged;  // the fallbacks replacing the same sensor, as the compensator
  if (!all_read(*axis)) {
    const model::AxisModel* parent = axis;
    for (const auto& f : parent->fallbacks) {
      if (!all_read(f)) continue;
      std::vector<std::string> missing;
      for (const auto& k : parent->key_sensors)
        if (!read(k)) missing.push_back(k);
      if (!parent->ambient_sensor.empty() && !read(parent->ambient_sensor)) missing.push_back(parent->ambient_sensor);
      averaged = FallbackGroup(*parent, f, all_read);
      fallback_note = fmt::format("{} not read in this file: predicted with {}, as the compensator does when that sensor "
                                  "is lost",
                                  fmt::join(missing, ", "), DescribeFallbacks(averaged));
      axis = &f;
      break;
    }
  }
  for (const auto& k : axis->key_sensors)
    if (!read(k))
      throw InputError(o.measurement, 0, fmt::format("t_{}_c", k),
                       fmt::format("the model's key sensor '{}' is not {} this file{}", k,
                                   m.SensorIndex(k) ? "read in" : "in",
                                   axis->fallbacks.empty() ? "" : " (nor are the keys of any of its fallback models)"));
  // Thermal lag (key_lag_s): through the logged history before the file when given (the file's
  // '# campaign_time_s:' is its start on the log's clock), else from the file's first reading.
  model::TemperatureHistory history;
  if (!o.temperature_log.empty()) {
    const auto start = m.Meta("campaign_time_s");
    const auto start_s = start ? ParseDouble(Trim(*start)) : std::nullopt;
    if (!start_s || !std::isfinite(*start_s))
      throw InputError(o.measurement, m.MetaLine("campaign_time_s"), "campaign_time_s",
                       "--temperature-log needs the file's '# campaign_time_s:' line (its start on the log's clock)");
    history = model::TemperatureHistoryFromLog(o.temperature_log, m, *start_s, axis->key_sensors);
  }
  // The motion-heat input needs the axis's travelled path before and during the file (the log's
  // <axis>_travel_mm): without it the model cannot give its thermal part, and says so.
  if (axis->HasMotionHeat() && !history.HasTravel())
    throw InputError(o.measurement, 0, "--temperature-log",
                     fmt::format("axis {}'s model has a motion-heat input (the axis's feed lagged by {} s): give "
                                 "--temperature-log with the machine log that has {}_travel_mm over the file's time",
                                 axis->axis, FormatShortest(axis->motion_lag_s), LowerAscii(axis->axis)));
  // As the compensator with a group of fallbacks: the first one's Er(x), plus the mean of the
  // group's thermal + room parts (residual = measured − Er(x)₀ − mean(total_g − Er(x)_g)).
  const auto geometric_um = [&](const model::AxisModel& a, const measure::MeasurementPoint& pt) {
    return model::Predict(a, pt.target_mm, pt.direction, {{}, std::nan(""), *coolant, false}).geometric_um;
  };
  const auto residual_of = [&](const std::vector<const model::AxisModel*>& group) {
    auto r = model::PredictionResidual(*group[0], m, *coolant, history.empty() ? nullptr : &history);
    for (std::size_t g = 1; g < group.size(); ++g) {
      const auto other = model::PredictionResidual(*group[g], m, *coolant, history.empty() ? nullptr : &history);
      for (std::size_t i = 0; i < r.points.size(); ++i)
        r.points[i].deviation_um += other.points[i].deviation_um + geometric_um(*group[g], m.points[i]) -
                                    geometric_um(*group[0], m.points[i]);
    }
    if (group.size() > 1)
      for (auto& pt : r.points) pt.deviation_um /= static_cast<double>(group.size());
    return r;
  };
  auto residual = residual_of(averaged.empty() ? std::vector<const model::AxisModel*>{axis} : averaged);
  // A sensor of the model lost DURING the test (read at some points, not at others): from the
  // first point it is missing, predicted as the compensator does from then on — with the fallbacks
  // for it (without the compensator's hand-over from the model's last correction) — and said.
  std::string partial_note;
  {
    std::vector<std::string> needed = axis->key_sensors;
    if (!axis->ambient_sensor.empty()) needed.push_back(axis->ambient_sensor);
    std::vector<std::size_t> lost_points;
    std::vector<std::string> lost;
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      bool point_lost = false;
      for (const auto& s : needed) {
        const auto idx = m.SensorIndex(s);
        if (idx && !std::isfinite(m.points[i].temperatures_c[*idx])) {
          point_lost = true;
          if (std::find(lost.begin(), lost.end(), s) == lost.end()) lost.push_back(s);
        }
      }
      if (point_lost) lost_points.push_back(i);
    }
    if (!lost_points.empty()) {
      const auto read_where_lost = [&](const model::AxisModel& a) {
        std::vector<std::string> s = a.key_sensors;
        if (!a.ambient_sensor.empty()) s.push_back(a.ambient_sensor);
        for (const auto& name : s) {
          const auto idx = m.SensorIndex(name);
          if (!idx) return false;
          for (std::size_t i : lost_points)
            if (!std::isfinite(m.points[i].temperatures_c[*idx])) return false;
        }
        return true;
      };
      std::vector<const model::AxisModel*> group;
      for (const auto& f : axis->fallbacks)
        if (read_where_lost(f)) {
          group = FallbackGroup(*axis, f, read_where_lost);
          break;
        }
      const std::string where = fmt::format("{} not read at {} of {} points (lost during the test, first at run {} {} "
                                            "{} mm)",
                                            fmt::join(lost, ", "), lost_points.size(), m.points.size(),
                                            m.points[lost_points.front()].run,
                                            DirectionSymbol(m.points[lost_points.front()].direction),
                                            FormatShortest(m.points[lost_points.front()].target_mm));
      if (group.empty()) {
        partial_note = "warning: " + where + ": those points predicted without it (no fallback model reads them)";
      } else {
        const auto fallback = residual_of(group);
        for (std::size_t i : lost_points) residual.points[i] = fallback.points[i];
        partial_note = "note: " + where + ": those points predicted with " + DescribeFallbacks(group) +
                       ", as the compensator does from then on (without its hand-over)";
      }
    }
  }
  const auto before = analysis::Evaluate(m);
  const auto after = analysis::Evaluate(residual);
  double ss_m = 0, ss_r = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    ss_m += m.points[i].deviation_um * m.points[i].deviation_um,
        ss_r += residual.points[i].deviation_um * residual.points[i].deviation_um;
  const double n = static_cast<double>(m.points.size());
  std::cout << fmt::format("{}: axis {}, coolant {}, {} points\n", o.measurement, axis_name, CoolantStateName(*coolant),
                           m.points.size());
  // Another machine's test (a sister machine, a mix-up): predicted, but said.
  const std::string file_machine(Trim(m.Meta("machine").value_or("")));
  if (!file_machine.empty() && !model.machine.empty() && file_machine != model.machine)
    std::cout << fmt::format("  warning: the file is of machine '{}', the model of '{}'\n", file_machine, model.machine);
  if (!fallback_note.empty()) std::cout << "  note: " << fallback_note << "\n";
  if (!partial_note.empty()) std::cout << "  " << partial_note << "\n";
  std::cout << fmt::format("  measured error        ISO 230-2 A {:>8.2f} µm   RMS {:>7.2f} µm\n", before.axis.A_um,
                           std::sqrt(ss_m / n));
  // A test measured through the compensation: subtracting the prediction counts the model twice.
  const bool compensated = measure::CompensationActive(m).value_or(false);
  if (compensated)
    std::cout << "  warning: measured with the compensation on ('# compensation: on'): its deviations already include "
                 "a correction, so measured − predicted subtracts the model a second time\n";
  std::cout << fmt::format("  measured − predicted  ISO 230-2 A {:>8.2f} µm   RMS {:>7.2f} µm   ({})\n", after.axis.A_um,
                           std::sqrt(ss_r / n),
                           compensated ? "not a remaining error: the file's own compensation is in it"
                                       : "what would remain after compensation");
  // The room outside what the fit saw: the ρ term was extrapolated for those points (never silent).
  if (const auto amb = axis->ambient_sensor.empty() ? std::nullopt : m.SensorIndex(axis->ambient_sensor)) {
    std::size_t outside = 0;
    for (const auto& pt : m.points) outside += axis->AmbientOutsideFittedRange(pt.temperatures_c[*amb]) ? 1 : 0;
    if (outside)
      std::cout << fmt::format("  warning: {} of {} points have {} outside the fitted {:.2f} … {:.2f} °C (room term "
                               "extrapolated)\n",
                               outside, m.points.size(), axis->ambient_sensor, axis->ambient_fitted_range_c[0],
                               axis->ambient_fitted_range_c[1]);
  }
  if (!o.residual_out.empty()) {
    measure::WriteMeasurementCsv(residual, o.residual_out);
    std::cout << fmt::format("wrote {} (deviation_um = measured − predicted)\n", o.residual_out);
  }
}

void RunPredict(const PredictOptions& o) {
  const auto model = model::ReadModelFile(o.model);
  if (o.input.Given() && o.measurement.empty())
    throw InputError("command line", 0, "--columns", "applies to --measurement only");
  if (!o.measurement.empty()) return RunPredictMeasurement(o, model);
  if (o.axis.empty()) throw InputError("command line", 0, "--axis", "required (or give --measurement)");
  if (!o.position_given) throw InputError("command line", 0, "--position-mm", "required (or give --measurement)");
  if (o.direction.empty()) throw InputError("command line", 0, "--direction", "required: + or -");
  const auto* axis = model.FindAxis(o.axis);
  if (!axis) {
    std::vector<std::string> names;
    for (const auto& a : model.axes) names.push_back(a.axis);
    throw InputError(o.model, 0, "--axis", fmt::format("the model has no axis '{}' (it has {})", o.axis, fmt::join(names, ", ")));
  }
  const auto dir = ParseDirection(o.direction);
  if (!dir) throw InputError("command line", 0, "--direction", fmt::format("'{}' is not + or -", o.direction));
  if (!std::isfinite(o.position_mm)) throw InputError("command line", 0, "--position-mm", "must be a finite number");
  const auto coolant = ParseCoolantState(o.coolant.empty() ? "off" : o.coolant);
  if (!coolant) throw InputError("command line", 0, "--coolant", fmt::format("'{}' is not off, flood, mist or air", o.coolant));

  std::map<std::string, double> given;
  for (const auto& t : o.temps) {
    const auto eq = t.find('=');
    if (eq == std::string::npos)
      throw InputError("command line", 0, "--temp", fmt::format("'{}' is not NAME=°C (e.g. nut=25.1)", t));
    const std::string name(Trim(t.substr(0, eq)));
    const auto v = ParseDouble(t.substr(eq + 1));
    if (!v || !std::isfinite(*v))
      throw InputError("command line", 0, "--temp", fmt::format("'{}': '{}' is not a temperature", name, t.substr(eq + 1)));
    if (name.empty()) throw InputError("command line", 0, "--temp", fmt::format("'{}' has no sensor name", t));
    if (auto why = ImplausibleTemperatureC(*v)) throw InputError("command line", 0, "--temp", name + ": " + *why);
    bool known = false;
    for (const auto& k : axis->key_sensors) known = known || k == name;
    for (const auto& f : axis->fallbacks)
      for (const auto& k : f.key_sensors) known = known || k == name;
    if (!known && name != axis->ambient_sensor)
      throw InputError("command line", 0, "--temp",
                       fmt::format("'{}' is not a key sensor of axis {} (key sensors: {})", name, o.axis,
                                   axis->key_sensors.empty() ? std::string("none") : fmt::format("{}", fmt::join(axis->key_sensors, ", "))));
    if (!given.emplace(name, *v).second)
      throw InputError("command line", 0, "--temp", fmt::format("sensor '{}' given twice", name));
  }
  // The room given twice (--ambient-c and --temp <ambient sensor>=…) with two values: which one
  // is meant is not ours to guess.
  if (const auto room = given.find(axis->ambient_sensor);
      room != given.end() && !std::isnan(o.ambient_c) && room->second != o.ambient_c)
    throw InputError("command line", 0, "--ambient-c",
                     fmt::format("{} °C, but --temp {}={} gives the ambient sensor another value; give it once",
                                 FormatShortest(o.ambient_c), room->first, FormatShortest(room->second)));
  std::vector<double> key_temps;
  const bool use_thermal = !o.geometric_only;
  // A key sensor of the model not given: the first fallback model (fitted without it) whose keys
  // all are, as the compensator does when that sensor is lost (docs/model-file.md).
  std::string fallback_note;
  const bool room_given = !std::isnan(o.ambient_c) || (!axis->ambient_sensor.empty() && given.count(axis->ambient_sensor));
  const auto all_given = [&](const model::AxisModel& a) {
    for (const auto& k : a.key_sensors)
      if (!given.count(k)) return false;
    return a.ambient_sensor.empty() || room_given;
  };
  std::vector<const model::AxisModel*> averaged;  // the fallbacks replacing the same sensor, as the compensator
  if (use_thermal && !all_given(*axis)) {
    const model::AxisModel* parent = axis;
    for (const auto& f : parent->fallbacks) {
      if (!all_given(f)) continue;
      std::vector<std::string> missing;
      for (const auto& k : parent->key_sensors)
        if (!given.count(k)) missing.push_back(k);
      if (!parent->ambient_sensor.empty() && !room_given) missing.push_back(parent->ambient_sensor + " (--ambient-c)");
      averaged = FallbackGroup(*parent, f, all_given);
      fallback_note = fmt::format("{} not given: {}, as the compensator uses when that sensor is lost",
                                  fmt::join(missing, ", "), DescribeFallbacks(averaged));
      axis = &f;
      break;
    }
  }
  for (const auto& k : axis->key_sensors) {
    auto it = given.find(k);
    if (it == given.end()) {
      if (use_thermal) {
        std::vector<std::string> fallbacks;
        for (const auto& f : axis->fallbacks) fallbacks.push_back(fmt::format("{}", fmt::join(f.key_sensors, " + ")));
        throw InputError("command line", 0, "--temp",
                         fmt::format("key sensor '{}' needs a temperature (--temp {}=…){}, or pass --geometric-only", k,
                                     k, fallbacks.empty() ? "" : fmt::format(", or those of a fallback model ({})",
                                                                             fmt::join(fallbacks, " or "))));
      }
      key_temps.push_back(std::numeric_limits<double>::quiet_NaN());
    } else {
      key_temps.push_back(it->second);
    }
  }
  double ambient = o.ambient_c;
  if (!std::isnan(ambient))
    if (auto why = ImplausibleTemperatureC(ambient)) throw InputError("command line", 0, "--ambient-c", *why);
  if (std::isnan(ambient) && !axis->ambient_sensor.empty())
    if (auto it = given.find(axis->ambient_sensor); it != given.end()) ambient = it->second;
  // Without the ambient reading the model would silently drop the ρ term and, when it measures key
  // rises above ambient, switch to the plain rise: a different prediction. Ask for it instead.
  if (use_thermal && std::isnan(ambient) && !axis->ambient_sensor.empty())
    throw InputError("command line", 0, "--ambient-c",
                     fmt::format("axis {} is modelled with the ambient sensor '{}'{}: give --ambient-c (its baseline "
                                 "is {:.2f} °C), or --geometric-only", o.axis, axis->ambient_sensor,
                                 axis->key_rise_above_ambient ? " (key rises are measured above ambient)" : "",
                                 axis->ambient_baseline_c));

  // The motion-heat input (the axis's lagged feed): asked for, as a key temperature is.
  const auto motion_for = [&](const model::AxisModel& a) {
    if (!a.HasMotionHeat() || !use_thermal) return 0.0;
    if (std::isnan(o.motion_m_per_min))
      throw InputError("command line", 0, "--motion-m-per-min",
                       fmt::format("axis {}'s model has a motion-heat input (the axis's feed lagged by {} s): give "
                                   "--motion-m-per-min (0: at rest for a few τ), or --geometric-only",
                                   o.axis, FormatShortest(a.motion_lag_s)));
    return o.motion_m_per_min;
  };
  model::ThermalState st{key_temps, ambient, *coolant, use_thermal, motion_for(*axis)};
  auto p = model::Predict(*axis, o.position_mm, *dir, st);
  if (averaged.size() > 1) {  // the mean of the fallbacks replacing the same sensor
    for (std::size_t g = 1; g < averaged.size(); ++g) {
      std::vector<double> temps;
      for (const auto& k : averaged[g]->key_sensors) temps.push_back(given.at(k));
      const auto q = model::Predict(*averaged[g], o.position_mm, *dir,
                                    {temps, ambient, *coolant, use_thermal, motion_for(*averaged[g])});
      p.thermal_um += q.thermal_um, p.ambient_um += q.ambient_um, p.total_um += q.total_um - q.geometric_um;
      p.tan_beta_um_per_mm += q.tan_beta_um_per_mm;
      p.tan_beta_limited = p.tan_beta_limited || q.tan_beta_limited;
      p.ambient_extrapolated = p.ambient_extrapolated || q.ambient_extrapolated;
    }
    const double n = static_cast<double>(averaged.size());
    p.total_um = p.geometric_um + (p.total_um - p.geometric_um) / n;
    p.thermal_um /= n, p.ambient_um /= n, p.tan_beta_um_per_mm /= n;
  }
  const auto& g = axis->For(*dir).geometric;
  const double lo = g.kind == model::GeometricError::Kind::kTable ? g.table_position_mm.front() : g.center_mm - g.half_span_mm;
  const double hi = g.kind == model::GeometricError::Kind::kTable ? g.table_position_mm.back() : g.center_mm + g.half_span_mm;
  const bool outside = o.position_mm < lo - 1e-9 || o.position_mm > hi + 1e-9;
  // Key temperatures outside what the fit saw: the thermal part is extrapolated.
  std::vector<std::string> temp_outside;
  for (std::size_t k = 0; k < axis->key_sensors.size() && k < axis->key_fitted_range_c.size(); ++k) {
    const double t = key_temps[k];
    const auto& r = axis->key_fitted_range_c[k];
    if (std::isfinite(t) && (t < r[0] - 1e-9 || t > r[1] + 1e-9))
      temp_outside.push_back(fmt::format("{} {} °C is outside the fitted {:.2f} … {:.2f} °C", axis->key_sensors[k],
                                         FormatShortest(t), r[0], r[1]));
  }
  if (p.ambient_extrapolated)
    temp_outside.push_back(fmt::format("{} {} °C is outside the fitted {:.2f} … {:.2f} °C", axis->ambient_sensor,
                                       FormatShortest(ambient), axis->ambient_fitted_range_c[0],
                                       axis->ambient_fitted_range_c[1]));
  const auto* gains = axis->For(*dir).GainsFor(*coolant);
  // Sensors given that the chosen model does not read (keys of another fallback only): said, not dropped silently.
  std::vector<std::string> unused;
  for (const auto& [name, value] : given)
    if (name != axis->ambient_sensor &&
        std::find(axis->key_sensors.begin(), axis->key_sensors.end(), name) == axis->key_sensors.end())
      unused.push_back(name);

  if (o.json) {
    nlohmann::json j{{"axis", o.axis},
                     {"position_mm", o.position_mm},
                     {"direction", std::string(1, DirectionSymbol(*dir))},
                     {"coolant", std::string(CoolantStateName(*coolant))},
                     {"geometric_um", p.geometric_um},
                     {"thermal_um", p.thermal_um},
                     {"ambient_um", p.ambient_um},
                     {"tan_beta_um_per_mm", p.tan_beta_um_per_mm},
                     {"error_um", p.total_um},
                     {"correction_um", model::CorrectionUm(p)},
                     {"outside_fitted_range", outside || p.position_outside_range},
                     {"temperatures_outside_fitted_range", temp_outside},
                     {"fallback_model", fallback_note.empty() ? nlohmann::json(nullptr) : nlohmann::json(axis->key_sensors)},
                     {"fallback_models_averaged", averaged.size()},
                     {"unused_sensors", unused}};
    if (axis->HasMotionHeat()) j["motion_m_per_min"] = st.motion_m_per_min;
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("axis {}, position {} mm, direction {} ({}), coolant {} (gains: {})\n", o.axis,
                           FormatShortest(o.position_mm), DirectionSymbol(*dir),
                           *dir == Direction::kForward ? "forward" : "reverse", CoolantStateName(*coolant),
                           gains ? std::string(CoolantStateName(gains->coolant)) : std::string("none"));
  std::cout << fmt::format("  geometric  Er(x)                  {:>10.3f} µm\n", p.geometric_um);
  std::cout << fmt::format("  thermal    tanβ·(Px − P0)         {:>10.3f} µm   (tanβ = {:.6f} µm/mm, Px = {:.3f} mm)\n",
                           p.thermal_um, p.tan_beta_um_per_mm, axis->reference_position_mm);
  if (axis->HasMotionHeat() && use_thermal)
    std::cout << fmt::format("  (tanβ includes the motion-heat input: {} m/min, the feed lagged by {} s)\n",
                             FormatShortest(st.motion_m_per_min), FormatShortest(axis->motion_lag_s));
  std::cout << fmt::format("  ambient    ρ·ΔT_env·(Px − P0)     {:>10.3f} µm\n", p.ambient_um);
  std::cout << fmt::format("  predicted error (actual − commanded) {:>8.3f} µm\n", p.total_um);
  std::cout << fmt::format("  correction (added to the command)    {:>8.3f} µm\n", model::CorrectionUm(p));
  if (p.position_outside_range)
    std::cout << fmt::format("  warning: {} mm is outside the measured range {} … {} mm (geometric part held at its end)\n",
                             FormatShortest(o.position_mm), FormatShortest(axis->measured_range_mm[0]),
                             FormatShortest(axis->measured_range_mm[1]));
  else if (outside)
    std::cout << fmt::format("  warning: {} mm is outside the fitted range {} … {} mm (extrapolated)\n",
                             FormatShortest(o.position_mm), FormatShortest(lo), FormatShortest(hi));
  for (const auto& w : temp_outside) std::cout << "  warning: " << w << " (thermal part extrapolated)\n";
  if (!use_thermal) std::cout << "  note: --geometric-only: thermal and ambient parts not applied\n";
  if (!fallback_note.empty()) std::cout << "  note: " << fallback_note << "\n";
  for (const auto& name : unused) std::cout << "  note: " << name << " is not used by this model (a key of another fallback model)\n";

}

void Setup(CLI::App& app) {
  auto o = std::make_shared<PredictOptions>();
  auto* cmd = app.add_subcommand("predict", "Predict the error and correction of one axis position from a model file");
  cmd->add_option("--model", o->model, "Model file (trueaxis fit)")->required();
  cmd->add_option("--axis", o->axis, "Axis name, e.g. X");
  cmd->add_option_function<double>(
      "--position-mm", [o](const double& v) { o->position_mm = v, o->position_given = true; },
      "Commanded machine coordinate P0 in mm");
  cmd->add_option("--direction", o->direction, "Direction of approach: + or -");
  cmd->add_option("--measurement", o->measurement,
                  "Predict every point of this measurement (canonical CSV, ecmc .dat or a mapped laser export; "
                  "held-out check) instead of one position");
  AddMeasurementInputOptions(cmd, o->input);
  cmd->add_option("--residual-out", o->residual_out, "With --measurement: write measured − predicted as a CSV");
  cmd->add_option("--temperature-log", o->temperature_log,
                  "With --measurement: the campaign's temperature_log.csv, so the model's key-sensor lag starts from "
                  "the history before the file (default: from the file's first reading)");
  cmd->add_option("--temp", o->temps, "Key-sensor temperatures NAME=°C, comma separated")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--ambient-c", o->ambient_c, "Ambient temperature in °C (for the ρ term)");
  cmd->add_option("--motion-m-per-min", o->motion_m_per_min,
                  "The motion-heat input of a model that has one: the axis's feed in m/min through the model's lag "
                  "(0: at rest)")
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--coolant", o->coolant, "Coolant state: off, flood, mist, air (default off, or the file's)");
  cmd->add_flag("--geometric-only", o->geometric_only, "Geometric part only (no temperatures needed)");
  cmd->add_flag("--json", o->json, "Print JSON instead of text");
  cmd->callback([o] { RunPredict(*o); });
}

CommandRegistrar reg("predict", Setup);

}  // namespace
}  // namespace trueaxis::cli
