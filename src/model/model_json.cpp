#include "trueaxis/model/model_json.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::model {
namespace {
using nlohmann::json;

const char* KindName(GeometricError::Kind k) { return k == GeometricError::Kind::kTable ? "table" : "polynomial"; }

json GeometricToJson(const GeometricError& g) {
  json j{{"kind", KindName(g.kind)}};
  if (g.kind == GeometricError::Kind::kPolynomial) {
    j["center_mm"] = g.center_mm;
    j["half_span_mm"] = g.half_span_mm;
    j["coefficients_um"] = g.coefficients_um;
  } else {
    j["position_mm"] = g.table_position_mm;
    j["error_um"] = g.table_error_um;
  }
  return j;
}

json DirectionToJson(const DirectionModel& d, const std::vector<KeyShifts>& shifts) {
  json thermal = json::array();
  for (std::size_t gi = 0; gi < d.thermal.size(); ++gi) {
    const auto& g = d.thermal[gi];
    json e = {{"coolant", std::string(CoolantStateName(g.coolant))},
              {"k_um_per_mm_per_c", g.k_um_per_mm_per_c},
              {"offset_um_per_mm", g.offset_um_per_mm}};
    // Absent = no key pivots (the seed's form; older files read as before).
    if (gi < shifts.size() && !shifts[gi].offset_um_per_c.empty()) {
      e["offset_um_per_c"] = shifts[gi].offset_um_per_c;
      e["ambient_offset_um_per_c"] = shifts[gi].ambient_offset_um_per_c;
    }
    // Absent = no envelope (older files read as before); an open end is written as null.
    auto end = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
    if (g.HasTanBetaRange()) e["tan_beta_range_um_per_mm"] = {end(g.min_tan_beta_um_per_mm), end(g.max_tan_beta_um_per_mm)};
    if (!g.key_rise_range_c.empty()) {
      json ranges = json::array();
      for (const auto& r : g.key_rise_range_c) ranges.push_back({r[0], r[1]});
      e["key_rise_range_c"] = std::move(ranges);
    }
    thermal.push_back(std::move(e));
  }
  return {{"geometric", GeometricToJson(d.geometric)}, {"thermal", thermal}};
}

// Field access with errors that name the JSON path.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& path, const std::string& why) const {
    throw InputError(source_, 0, path, why);
  }
  const json& Get(const json& obj, const std::string& path, const char* key) const {
    if (!obj.is_object()) Fail(path, "expected an object");
    auto it = obj.find(key);
    if (it == obj.end()) Fail(Join(path, key), "required field is missing");
    return *it;
  }
  double Number(const json& obj, const std::string& path, const char* key) const {
    const json& v = Get(obj, path, key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) Fail(Join(path, key), "expected a finite number");
    return v.get<double>();
  }
  double NumberOr(const json& obj, const std::string& path, const char* key, double dflt) const {
    return obj.contains(key) ? Number(obj, path, key) : dflt;
  }
  std::string String(const json& obj, const std::string& path, const char* key) const {
    const json& v = Get(obj, path, key);
    if (!v.is_string()) Fail(Join(path, key), "expected a string");
    return v.get<std::string>();
  }
  std::string StringOr(const json& obj, const std::string& path, const char* key, std::string dflt) const {
    return obj.contains(key) ? String(obj, path, key) : dflt;
  }
  std::vector<double> Numbers(const json& obj, const std::string& path, const char* key) const {
    const json& v = Get(obj, path, key);
    if (!v.is_array()) Fail(Join(path, key), "expected an array of numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
        Fail(fmt::format("{}[{}]", Join(path, key), i), "expected a finite number");
      out.push_back(v[i].get<double>());
    }
    return out;
  }
  // A value no machine's model holds (core/plausibility.hpp: kelvin, 1e308, a lost unit), refused
  // with its path: Predict would turn it into ±inf or a 300-digit correction.
  void Plausible(const std::string& path, const std::optional<std::string>& why) const {
    if (why) Fail(path, *why);
  }
  void AllPlausible(const std::string& path, const std::vector<double>& values,
                    std::optional<std::string> (*check)(double)) const {
    for (std::size_t i = 0; i < values.size(); ++i) Plausible(fmt::format("{}[{}]", path, i), check(values[i]));
  }
  static std::string Join(const std::string& path, const char* key) {
    return path.empty() ? std::string(key) : path + "." + key;
  }

 private:
  std::string source_;
};

// Half the travel a polynomial Er(x) was fitted on: below a micrometre u = (x − c)/h overflows.
constexpr double kMinHalfSpanMm = 1e-3;
constexpr int kSpanSamples = 64;  // points over u in [−1, 1] at which a polynomial's Er is checked

GeometricError GeometricFromJson(const Reader& r, const json& j, const std::string& path) {
  GeometricError g;
  const std::string kind = r.String(j, path, "kind");
  if (kind == "polynomial") {
    g.kind = GeometricError::Kind::kPolynomial;
    g.center_mm = r.Number(j, path, "center_mm");
    r.Plausible(Reader::Join(path, "center_mm"), ImplausiblePositionMm(g.center_mm));
    g.half_span_mm = r.Number(j, path, "half_span_mm");
    if (!(g.half_span_mm >= kMinHalfSpanMm))
      r.Fail(Reader::Join(path, "half_span_mm"), fmt::format("{} mm: must be at least {} mm (half the travel the "
                                                             "polynomial was fitted on)", g.half_span_mm, kMinHalfSpanMm));
    r.Plausible(Reader::Join(path, "half_span_mm"), ImplausiblePositionMm(g.half_span_mm));
    g.coefficients_um = r.Numbers(j, path, "coefficients_um");
    if (g.coefficients_um.empty()) r.Fail(Reader::Join(path, "coefficients_um"), "needs at least one coefficient");
    // Over the span it was fitted on (u in [−1, 1]) Er(x) is a positioning error like a measured one.
    for (int i = 0; i <= kSpanSamples; ++i) {
      const double x = g.center_mm + (-1.0 + 2.0 * i / kSpanSamples) * g.half_span_mm;
      if (auto why = ImplausibleDeviationUm(g.Evaluate(x)))
        r.Fail(Reader::Join(path, "coefficients_um"), fmt::format("give Er({:g} mm), within the fitted span: {}", x, *why));
    }
  } else if (kind == "table") {
    g.kind = GeometricError::Kind::kTable;
    g.table_position_mm = r.Numbers(j, path, "position_mm");
    g.table_error_um = r.Numbers(j, path, "error_um");
    r.AllPlausible(Reader::Join(path, "position_mm"), g.table_position_mm, ImplausiblePositionMm);
    r.AllPlausible(Reader::Join(path, "error_um"), g.table_error_um, ImplausibleDeviationUm);
    if (g.table_position_mm.size() != g.table_error_um.size())
      r.Fail(Reader::Join(path, "error_um"), "must have as many entries as position_mm");
    if (g.table_position_mm.empty()) r.Fail(Reader::Join(path, "position_mm"), "needs at least one point");
    for (std::size_t i = 1; i < g.table_position_mm.size(); ++i)
      if (!(g.table_position_mm[i] > g.table_position_mm[i - 1]))
        r.Fail(fmt::format("{}.position_mm[{}]", path, i), "positions must be strictly ascending");
  } else {
    r.Fail(Reader::Join(path, "kind"), fmt::format("'{}' is not 'polynomial' or 'table'", kind));
  }
  return g;
}

DirectionModel DirectionFromJson(const Reader& r, const json& j, const std::string& path, std::size_t n_keys,
                                 std::size_t n_sensor_keys, std::vector<KeyShifts>& shifts) {
  DirectionModel d;
  d.geometric = GeometricFromJson(r, r.Get(j, path, "geometric"), Reader::Join(path, "geometric"));
  if (j.contains("thermal")) {
    const json& t = j["thermal"];
    const std::string tpath = Reader::Join(path, "thermal");
    if (!t.is_array()) r.Fail(tpath, "expected an array");
    for (std::size_t i = 0; i < t.size(); ++i) {
      const std::string ep = fmt::format("{}[{}]", tpath, i);
      ThermalGains g;
      const std::string coolant = r.String(t[i], ep, "coolant");
      auto state = ParseCoolantState(coolant);
      if (!state) r.Fail(Reader::Join(ep, "coolant"), fmt::format("unknown coolant state '{}'", coolant));
      g.coolant = *state;
      g.k_um_per_mm_per_c = r.Numbers(t[i], ep, "k_um_per_mm_per_c");
      if (g.k_um_per_mm_per_c.size() != n_keys)
        r.Fail(Reader::Join(ep, "k_um_per_mm_per_c"),
               fmt::format("has {} gains but the axis needs {} (one per key sensor, and one more with motion_heat)",
                           g.k_um_per_mm_per_c.size(), n_keys));
      for (std::size_t k = 0; k < n_sensor_keys; ++k)  // the motion gain (per m/min) after them is not per °C
        r.Plausible(fmt::format("{}.k_um_per_mm_per_c[{}]", ep, k), ImplausibleExpansionUmPerMmPerC(g.k_um_per_mm_per_c[k]));
      g.offset_um_per_mm = r.NumberOr(t[i], ep, "offset_um_per_mm", 0);
      if (t[i].contains("offset_um_per_c")) {
        KeyShifts ks;
        ks.offset_um_per_c = r.Numbers(t[i], ep, "offset_um_per_c");
        if (ks.offset_um_per_c.size() != n_keys)
          r.Fail(Reader::Join(ep, "offset_um_per_c"),
                 fmt::format("has {} offsets but the axis needs {} (one per key sensor, and one more with motion_heat)",
                             ks.offset_um_per_c.size(), n_keys));
        r.AllPlausible(Reader::Join(ep, "offset_um_per_c"), ks.offset_um_per_c, ImplausibleDeviationUm);
        ks.ambient_offset_um_per_c = r.NumberOr(t[i], ep, "ambient_offset_um_per_c", 0);
        r.Plausible(Reader::Join(ep, "ambient_offset_um_per_c"), ImplausibleDeviationUm(ks.ambient_offset_um_per_c));
        shifts.resize(i + 1);
        shifts[i] = std::move(ks);
      }
      if (t[i].contains("tan_beta_range_um_per_mm")) {
        const std::string rp = Reader::Join(ep, "tan_beta_range_um_per_mm");
        const json& range = t[i]["tan_beta_range_um_per_mm"];
        if (!range.is_array() || range.size() != 2) r.Fail(rp, "expected [low, high] (µm/mm; null = open)");
        for (std::size_t e = 0; e < 2; ++e) {
          if (range[e].is_null()) continue;
          if (!range[e].is_number() || !std::isfinite(range[e].get<double>()))
            r.Fail(fmt::format("{}[{}]", rp, e), "expected a finite number or null");
          (e == 0 ? g.min_tan_beta_um_per_mm : g.max_tan_beta_um_per_mm) = range[e].get<double>();
        }
        if (!(g.min_tan_beta_um_per_mm <= g.max_tan_beta_um_per_mm)) r.Fail(rp, "low must not exceed high");
      }
      if (t[i].contains("key_rise_range_c")) {
        const std::string rp = Reader::Join(ep, "key_rise_range_c");
        const json& ranges = t[i]["key_rise_range_c"];
        if (!ranges.is_array() || ranges.size() != n_keys)
          r.Fail(rp, fmt::format("expected one [low, high] per key sensor in °C, and one in m/min with motion_heat ({})", n_keys));
        for (std::size_t k = 0; k < ranges.size(); ++k) {
          const json& e = ranges[k];
          const std::string kp = fmt::format("{}[{}]", rp, k);
          if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number())
            r.Fail(kp, "expected [low, high] in °C");
          const double lo = e[0].get<double>(), hi = e[1].get<double>();
          if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) r.Fail(kp, "expected finite low <= high");
          g.key_rise_range_c.push_back({lo, hi});
        }
      }
      for (const auto& earlier : d.thermal)
        if (earlier.coolant == g.coolant)
          r.Fail(Reader::Join(ep, "coolant"), fmt::format("coolant '{}' has gains twice", coolant));
      d.thermal.push_back(std::move(g));
    }
    // A coolant state without its own gains uses the `off` entry (GainsFor): without one it would
    // take another coolant's gains, e.g. predict a dry machine with the flood gains.
    const bool has_off = std::any_of(d.thermal.begin(), d.thermal.end(),
                                     [](const ThermalGains& g) { return g.coolant == CoolantState::kOff; });
    if (!d.thermal.empty() && !has_off)
      r.Fail(tpath, "has no \"off\" entry: a coolant state without its own gains would use another coolant's gains "
                    "(the fitter always writes the off gains first)");
  }
  return d;
}


json AxisToJson(const AxisModel& a) {
  json ja{{"axis", a.axis},
          {"reference_position_mm", a.reference_position_mm},
          {"key_sensors", a.key_sensors},
          {"baseline_temp_c", a.baseline_temp_c},
          {"rho_um_per_mm_per_c", a.rho_um_per_mm_per_c},
          {"forward", DirectionToJson(a.directions[0], a.key_shifts[0])},
          {"reverse", DirectionToJson(a.directions[1], a.key_shifts[1])}};
  if (!a.ambient_sensor.empty()) {
    ja["ambient_sensor"] = a.ambient_sensor;
    ja["ambient_baseline_c"] = a.ambient_baseline_c;
  }
  ja["key_temperature_rise"] = a.key_rise_above_ambient ? "above_ambient" : "from_baseline";
  if (a.HasKeyLag()) ja["key_lag_s"] = a.key_lag_s;  // absent = no lag (older readers see today's model)
  if (a.HasKeyLag() && a.key_lag_fall_factor != 1) ja["key_lag_fall_factor"] = a.key_lag_fall_factor;
  if (a.HasMotionHeat())  // the live input it needs, stated for whoever wires a real CNC to it
    ja["motion_heat"] = {{"tau_s", a.motion_lag_s},
                         {"input", "axis position every cycle (feed |dP/dt| in m/min, lagged by tau_s)"},
                         {"gain", "last entry of each gains entry's k_um_per_mm_per_c (µm/mm per m/min)"}};
  json loss = json::object();  // absent = no coolant loss
  for (std::size_t c = 0; c < a.key_loss_s.size(); ++c)
    if (!a.key_loss_s[c].empty()) loss[std::string(CoolantStateName(static_cast<CoolantState>(c)))] = a.key_loss_s[c];
  if (!loss.empty()) ja["key_loss_s"] = std::move(loss);
  if (!a.key_fitted_range_c.empty()) ja["key_fitted_range_c"] = a.key_fitted_range_c;
  if (!a.ambient_sensor.empty() && std::isfinite(a.ambient_fitted_range_c[0]) && std::isfinite(a.ambient_fitted_range_c[1]))
    ja["ambient_fitted_range_c"] = a.ambient_fitted_range_c;
  if (a.HasMeasuredRange()) ja["measured_range_mm"] = a.measured_range_mm;
  if (!a.replaces.empty()) ja["replaces"] = a.replaces;
  if (!a.fallbacks.empty()) {
    json fb = json::array();
    for (const auto& f : a.fallbacks) fb.push_back(AxisToJson(f));
    ja["fallbacks"] = std::move(fb);
  }
  return ja;
}

}  // namespace

nlohmann::json ModelToJson(const CompositeModel& model) {
  json axes = json::array();
  for (const auto& a : model.axes) axes.push_back(AxisToJson(a));
  json sources = json::array();
  for (const auto& s : model.sources) {
    json js{{"path", s.path}, {"sha256", s.sha256}, {"state", s.state}};
    if (!s.coolant.empty()) js["coolant"] = s.coolant;
    if (!s.axis.empty()) js["axis"] = s.axis;
    if (!s.temperature_log.empty() && std::isfinite(s.start_time_s)) {
      js["temperature_log"] = s.temperature_log;
      js["temperature_log_sha256"] = s.temperature_log_sha256;
      js["start_time_s"] = s.start_time_s;
    }
    sources.push_back(std::move(js));
  }
  json lineage = json::array();
  for (const auto& l : model.lineage)
    lineage.push_back({{"revision", l.revision}, {"sha256", l.sha256}, {"created_utc", l.created_utc}});
  return {{"format", "trueaxis-model"},
          {"format_version", model.format_version},
          {"machine", model.machine},
          {"created_utc", model.created_utc},
          {"generator", model.generator},
          {"revision", model.revision},
          {"parent_sha256", model.parent_sha256},
          {"sign_convention", "values are errors (actual - commanded); correction = -error"},
          {"sources", sources},
          {"lineage", lineage},
          {"axes", axes},
          {"fit_summary", model.fit_summary}};
}

namespace {
// A key's τ while it falls, as a multiple of its τ while it rises: beyond this the key would freeze.
constexpr double kMaxLagFallFactor = 1000;

// One axis object (also a fallback's, `nested` then: no fallbacks of its own).
AxisModel AxisFromJson(const Reader& r, const json& ja, const std::string& p, bool nested) {
  AxisModel a;
  a.axis = r.String(ja, p, "axis");
  a.reference_position_mm = r.Number(ja, p, "reference_position_mm");
  r.Plausible(Reader::Join(p, "reference_position_mm"), ImplausiblePositionMm(a.reference_position_mm));
  if (ja.contains("key_sensors")) {
    const json& ks = ja["key_sensors"];
    if (!ks.is_array()) r.Fail(Reader::Join(p, "key_sensors"), "expected an array of names");
    for (std::size_t k = 0; k < ks.size(); ++k) {
      if (!ks[k].is_string()) r.Fail(fmt::format("{}.key_sensors[{}]", p, k), "expected a sensor name");
      a.key_sensors.push_back(ks[k].get<std::string>());
    }
  }
  a.baseline_temp_c = ja.contains("baseline_temp_c") ? r.Numbers(ja, p, "baseline_temp_c") : std::vector<double>{};
  if (a.baseline_temp_c.size() != a.key_sensors.size())
    r.Fail(Reader::Join(p, "baseline_temp_c"), "needs one temperature per key sensor");
  r.AllPlausible(Reader::Join(p, "baseline_temp_c"), a.baseline_temp_c, ImplausibleTemperatureC);
  if (ja.contains("key_fitted_range_c")) {
    const json& fr = ja["key_fitted_range_c"];
    const std::string where = Reader::Join(p, "key_fitted_range_c");
    if (!fr.is_array() || fr.size() != a.key_sensors.size()) r.Fail(where, "needs one [low, high] per key sensor");
    for (const auto& e : fr) {
      if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number() || e[0].get<double>() > e[1].get<double>())
        r.Fail(where, "each entry is [low °C, high °C] with low <= high");
      a.key_fitted_range_c.push_back({e[0].get<double>(), e[1].get<double>()});
      for (double t : a.key_fitted_range_c.back()) r.Plausible(where, ImplausibleTemperatureC(t));
    }
  }
  if (ja.contains("key_loss_s")) {
    const std::string lp = Reader::Join(p, "key_loss_s");
    const json& loss = ja["key_loss_s"];
    if (!loss.is_object()) r.Fail(lp, "expected an object {\"<coolant>\": [seconds per key sensor]}");
    for (const auto& [name, values] : loss.items()) {
      const auto c = ParseCoolantState(name);
      if (!c) r.Fail(Reader::Join(lp, name.c_str()), fmt::format("unknown coolant state '{}'", name));
      auto v = r.Numbers(loss, lp, name.c_str());
      if (v.size() != a.key_sensors.size()) r.Fail(Reader::Join(lp, name.c_str()), "needs one time constant per key sensor");
      for (double t : v)
        if (!(t >= 0) || !std::isfinite(t)) r.Fail(Reader::Join(lp, name.c_str()), "must be finite seconds >= 0");
      r.AllPlausible(Reader::Join(lp, name.c_str()), v, ImplausibleTimeS);
      a.key_loss_s[static_cast<std::size_t>(*c)] = std::move(v);
    }
  }
  if (ja.contains("key_lag_s")) {
    a.key_lag_s = r.Numbers(ja, p, "key_lag_s");
    if (a.key_lag_s.size() != a.key_sensors.size())
      r.Fail(Reader::Join(p, "key_lag_s"), "needs one time constant per key sensor");
    for (std::size_t k = 0; k < a.key_lag_s.size(); ++k)
      if (!(a.key_lag_s[k] >= 0) || !std::isfinite(a.key_lag_s[k]))
        r.Fail(fmt::format("{}.key_lag_s[{}]", p, k), "must be a finite number of seconds >= 0");
    r.AllPlausible(Reader::Join(p, "key_lag_s"), a.key_lag_s, ImplausibleTimeS);
  }
  a.key_lag_fall_factor = r.NumberOr(ja, p, "key_lag_fall_factor", 1);
  if (!(a.key_lag_fall_factor >= 1) || !(a.key_lag_fall_factor <= kMaxLagFallFactor))
    r.Fail(Reader::Join(p, "key_lag_fall_factor"),
           fmt::format("must be a factor from 1 to {} (1: one τ both ways; the fitter tries 1 … 8)", kMaxLagFallFactor));
  if (ja.contains("motion_heat")) {
    const std::string mp = Reader::Join(p, "motion_heat");
    const json& mh = ja["motion_heat"];
    if (!mh.is_object()) r.Fail(mp, "expected an object {\"tau_s\": seconds}");
    a.motion_lag_s = r.Number(mh, mp, "tau_s");
    if (!(a.motion_lag_s > 0) || !std::isfinite(a.motion_lag_s)) r.Fail(Reader::Join(mp, "tau_s"), "must be finite seconds > 0");
    r.Plausible(Reader::Join(mp, "tau_s"), ImplausibleTimeS(a.motion_lag_s));
  }
  a.rho_um_per_mm_per_c = r.NumberOr(ja, p, "rho_um_per_mm_per_c", 0);
  r.Plausible(Reader::Join(p, "rho_um_per_mm_per_c"), ImplausibleExpansionUmPerMmPerC(a.rho_um_per_mm_per_c));
  a.ambient_sensor = r.StringOr(ja, p, "ambient_sensor", "");
  if (!a.ambient_sensor.empty()) {
    a.ambient_baseline_c = r.Number(ja, p, "ambient_baseline_c");
    r.Plausible(Reader::Join(p, "ambient_baseline_c"), ImplausibleTemperatureC(a.ambient_baseline_c));
  }
  if (ja.contains("ambient_fitted_range_c")) {
    const std::string where = Reader::Join(p, "ambient_fitted_range_c");
    if (a.ambient_sensor.empty()) r.Fail(where, "needs ambient_sensor");
    const auto range = r.Numbers(ja, p, "ambient_fitted_range_c");
    if (range.size() != 2 || !std::isfinite(range[0]) || !std::isfinite(range[1]) || range[0] > range[1])
      r.Fail(where, "expected [low °C, high °C] with low <= high");
    a.ambient_fitted_range_c = {range[0], range[1]};
    r.AllPlausible(where, range, ImplausibleTemperatureC);
  }
  if (ja.contains("measured_range_mm")) {
    const std::string where = Reader::Join(p, "measured_range_mm");
    const auto range = r.Numbers(ja, p, "measured_range_mm");
    if (range.size() != 2 || !std::isfinite(range[0]) || !std::isfinite(range[1]) || !(range[0] < range[1]))
      r.Fail(where, "expected [first mm, last mm] with first < last");
    r.AllPlausible(where, range, ImplausiblePositionMm);
    a.measured_range_mm = {range[0], range[1]};
  }
  const std::string rise = r.StringOr(ja, p, "key_temperature_rise", "from_baseline");
  if (rise == "above_ambient") {
    if (a.ambient_sensor.empty())
      r.Fail(Reader::Join(p, "key_temperature_rise"), "\"above_ambient\" needs ambient_sensor and ambient_baseline_c");
    a.key_rise_above_ambient = true;
  } else if (rise != "from_baseline") {
    r.Fail(Reader::Join(p, "key_temperature_rise"),
           fmt::format("'{}' is not \"from_baseline\" or \"above_ambient\"", rise));
  }
  a.directions[0] = DirectionFromJson(r, r.Get(ja, p, "forward"), Reader::Join(p, "forward"), a.GainCount(),
                                      a.key_sensors.size(), a.key_shifts[0]);
  a.directions[1] = DirectionFromJson(r, r.Get(ja, p, "reverse"), Reader::Join(p, "reverse"), a.GainCount(),
                                      a.key_sensors.size(), a.key_shifts[1]);
  if (ja.contains("replaces")) {
    if (!nested) r.Fail(Reader::Join(p, "replaces"), "only a fallback model replaces a sensor");
    a.replaces = r.String(ja, p, "replaces");
  }
  if (ja.contains("fallbacks")) {
    const std::string fp = Reader::Join(p, "fallbacks");
    const json& fb = ja["fallbacks"];
    if (nested) r.Fail(fp, "a fallback model has no fallbacks of its own");
    if (!fb.is_array()) r.Fail(fp, "expected an array of axis models");
    if (fb.size() > AxisModel::kMaxFallbacks)
      r.Fail(fp, fmt::format("{} fallback models, at most {}", fb.size(), AxisModel::kMaxFallbacks));
    for (std::size_t k = 0; k < fb.size(); ++k) {
      const std::string q = fmt::format("{}[{}]", fp, k);
      AxisModel f = AxisFromJson(r, fb[k], q, true);
      if (f.axis != a.axis) r.Fail(Reader::Join(q, "axis"), fmt::format("is '{}', not the axis '{}' it stands in for", f.axis, a.axis));
      // It stands in for a lost sensor: it must do without at least one of the axis's keys or its
      // ambient sensor.
      bool omits_one = !a.ambient_sensor.empty() && f.ambient_sensor != a.ambient_sensor;
      for (const auto& name : a.key_sensors)
        omits_one = omits_one || std::find(f.key_sensors.begin(), f.key_sensors.end(), name) == f.key_sensors.end();
      if (f.key_sensors.empty() || !omits_one)
        r.Fail(Reader::Join(q, "key_sensors"),
               fmt::format("must name key sensors and do without at least one of the axis's ({}{})",
                           fmt::join(a.key_sensors, ", "), a.ambient_sensor.empty() ? "" : " or its ambient sensor " + a.ambient_sensor));
      // The sensor it stands in for: one of the axis's, and one it does without.
      if (!f.replaces.empty()) {
        const bool is_key = std::find(a.key_sensors.begin(), a.key_sensors.end(), f.replaces) != a.key_sensors.end();
        const bool is_room = !a.ambient_sensor.empty() && f.replaces == a.ambient_sensor;
        if (!is_key && !is_room)
          r.Fail(Reader::Join(q, "replaces"), fmt::format("'{}' is not a key sensor ({}) or the ambient sensor of the axis",
                                                         f.replaces, fmt::join(a.key_sensors, ", ")));
        const bool uses_it = is_room ? f.ambient_sensor == f.replaces
                                     : std::find(f.key_sensors.begin(), f.key_sensors.end(), f.replaces) != f.key_sensors.end();
        if (uses_it) r.Fail(Reader::Join(q, "replaces"), fmt::format("'{}' is a sensor this fallback itself uses", f.replaces));
      }
      a.fallbacks.push_back(std::move(f));
    }
  }
  return a;
}

}  // namespace

CompositeModel ModelFromJson(const nlohmann::json& doc, const std::string& source) {
  Reader r(source);
  if (!doc.is_object()) r.Fail("", "a model file is a JSON object");
  if (r.StringOr(doc, "", "format", "") != "trueaxis-model") r.Fail("format", "expected \"trueaxis-model\"");
  CompositeModel m;
  const double version = r.Number(doc, "", "format_version");
  if (version != CompositeModel::kFormatVersion)
    r.Fail("format_version", fmt::format("version {} is not supported (this build reads {})", version,
                                         CompositeModel::kFormatVersion));
  m.machine = r.StringOr(doc, "", "machine", "");
  m.created_utc = r.StringOr(doc, "", "created_utc", "");
  m.generator = r.StringOr(doc, "", "generator", "");
  m.revision = static_cast<int>(r.NumberOr(doc, "", "revision", 1));
  m.parent_sha256 = r.StringOr(doc, "", "parent_sha256", "");
  if (doc.contains("sources")) {
    const json& s = doc["sources"];
    if (!s.is_array()) r.Fail("sources", "expected an array");
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::string p = fmt::format("sources[{}]", i);
      m.sources.push_back({r.String(s[i], p, "path"), r.StringOr(s[i], p, "sha256", ""), r.StringOr(s[i], p, "state", ""),
                           r.StringOr(s[i], p, "coolant", ""), r.StringOr(s[i], p, "axis", ""),
                           r.StringOr(s[i], p, "temperature_log", ""), r.StringOr(s[i], p, "temperature_log_sha256", ""),
                           r.NumberOr(s[i], p, "start_time_s", std::numeric_limits<double>::quiet_NaN())});
    }
  }
  if (doc.contains("lineage")) {
    const json& l = doc["lineage"];
    if (!l.is_array()) r.Fail("lineage", "expected an array");
    for (std::size_t i = 0; i < l.size(); ++i) {
      const std::string p = fmt::format("lineage[{}]", i);
      LineageEntry e;
      e.revision = static_cast<int>(r.Number(l[i], p, "revision"));
      e.sha256 = r.StringOr(l[i], p, "sha256", "");
      e.created_utc = r.StringOr(l[i], p, "created_utc", "");
      m.lineage.push_back(std::move(e));
    }
  }
  const json& axes = r.Get(doc, "", "axes");
  if (!axes.is_array() || axes.empty()) r.Fail("axes", "expected a non-empty array");
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const std::string p = fmt::format("axes[{}]", i);
    const json& ja = axes[i];
    AxisModel a = AxisFromJson(r, ja, p, false);
    if (m.FindAxis(a.axis)) r.Fail(Reader::Join(p, "axis"), fmt::format("axis '{}' is given twice", a.axis));
    m.axes.push_back(std::move(a));
  }
  if (doc.contains("fit_summary")) m.fit_summary = doc["fit_summary"];
  return m;
}

CompositeModel ReadModelFile(const std::string& path) {
  const std::string text = ReadTextFile(path);
  return ModelFromJson(ParseJsonOrThrow(text, path), path);
}

std::shared_ptr<const CompositeModel> ReadSharedModelFile(const std::string& path) {
  static std::mutex mu;
  struct Read {
    std::string text;
    std::weak_ptr<const CompositeModel> model;
  };
  static std::unordered_map<std::string, Read> read;  // by path: the bytes last read there and their model
  std::string text = ReadTextFile(path);
  std::lock_guard<std::mutex> lock(mu);
  Read& last = read[path];
  if (last.text == text)
    if (auto model = last.model.lock()) return model;
  auto model = std::make_shared<const CompositeModel>(ModelFromJson(ParseJsonOrThrow(text, path), path));
  last = {std::move(text), model};
  return model;
}

void WriteModelFile(const CompositeModel& model, const std::string& path) {
  WriteTextFile(path, ModelToJson(model).dump(2) + "\n");
}

}  // namespace trueaxis::model
