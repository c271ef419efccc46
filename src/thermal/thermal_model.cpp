#include "trueaxis/thermal/thermal_model.hpp"

#include <set>

#include <fmt/format.h>

#include "json_fields.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/thermal/hysteresis_model.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/linear_model.hpp"
#include "trueaxis/thermal/pso_bp_network.hpp"

namespace trueaxis::thermal {

const char* ThermalIntervalName(ThermalInterval i) {
  switch (i) {
    case ThermalInterval::kHeating: return "heating";
    case ThermalInterval::kSteady: return "steady";
    case ThermalInterval::kCooling: return "cooling";
    case ThermalInterval::kStartUp: return "start-up";
  }
  return "?";
}

std::vector<ThermalInterval> ThermalErrorModel::ClassifyRows(const ThermalSeries& series) const {
  return std::vector<ThermalInterval>(static_cast<std::size_t>(series.Rows()), ThermalInterval::kSteady);
}

Eigen::MatrixXd PredictSeries(const ThermalErrorModel& model, const ThermalSeries& series) {
  const auto& need = model.InputSensors();
  const ThermalSeries s = WithLaggedInputs(series, need);  // lagged inputs computed from their sensors
  std::vector<Eigen::Index> cols;
  for (const auto& name : need) {
    auto idx = s.TemperatureIndex(name);
    if (!idx) {
      std::string have;
      for (const auto& t : s.temperature_names) have += (have.empty() ? "" : ", ") + t;
      throw InputError(s.source, 0, name,
                       fmt::format("the model needs temperature '{}' but the series has only: {}", name, have));
    }
    cols.push_back(static_cast<Eigen::Index>(*idx));
  }
  if (model.UsesPosition() && !s.has_position)
    throw InputError(s.source, 0, "position_mm", "the model uses the axis position but the series has no position_mm");
  std::vector<ThermalInterval> intervals = model.ClassifyRows(s);
  const Eigen::Index n = s.Rows();
  Eigen::MatrixXd out(n, static_cast<Eigen::Index>(model.Channels().size()));
  std::vector<double> temps(cols.size()), pred(model.Channels().size());
  for (Eigen::Index r = 0; r < n; ++r) {
    for (std::size_t k = 0; k < cols.size(); ++k) {
      temps[k] = s.temperatures_c(r, cols[k]);
      if (std::isnan(temps[k]))
        throw InputError(s.source, s.LineOf(r), "t_" + need[k] + "_c", "temperature missing; clean the series first");
    }
    ThermalSample sample{temps, s.has_position ? s.position_mm[static_cast<std::size_t>(r)] : 0.0,
                         intervals[static_cast<std::size_t>(r)]};
    model.Predict(sample, pred);
    for (std::size_t c = 0; c < pred.size(); ++c) out(r, static_cast<Eigen::Index>(c)) = pred[c];
  }
  return out;
}

namespace {

std::unique_ptr<ThermalErrorModel> ModelOfKind(const nlohmann::json& doc, const std::string& source) {
  detail::JsonFields f(source);
  const std::string kind = f.String(doc, "", "kind");
  if (kind == "linear") return std::make_unique<LinearThermalModel>(LinearThermalModel::FromJson(doc, source, ""));
  if (kind == "pso_bp") return std::make_unique<PsoBpNetworkModel>(PsoBpNetworkModel::FromJson(doc, source, ""));
  if (kind == "hysteresis")
    return std::make_unique<HysteresisThermalModel>(HysteresisThermalModel::FromJson(doc, source, ""));
  f.Fail("kind", "'" + kind + "' is not a thermal model kind (linear, pso_bp, hysteresis)");
}

// A name listed twice: the prediction CSV would get two columns of one name, and an input sensor
// twice feeds one reading into two coefficients meant for two sensors.
void RefuseRepeatedNames(const std::vector<std::string>& names, const std::string& field, const detail::JsonFields& f) {
  std::set<std::string> seen;
  for (const auto& n : names)
    if (!seen.insert(n).second) f.Fail(field, fmt::format("'{}' is listed twice", n));
}

}  // namespace

std::unique_ptr<ThermalErrorModel> ThermalModelFromJson(const nlohmann::json& doc, const std::string& source) {
  auto model = ModelOfKind(doc, source);
  const detail::JsonFields f(source);
  RefuseRepeatedNames(model->Channels(), "channels", f);
  RefuseRepeatedNames(model->InputSensors(), "sensors", f);
  return model;
}

std::unique_ptr<ThermalErrorModel> ReadThermalModelFile(const std::string& path) {
  const std::string text = ReadTextFile(path);
  const nlohmann::json doc = ParseJsonOrThrow(text, path);
  if (doc.contains("model") && doc["model"].is_object()) {
    // The wrapper WriteThermalModelFile writes: another program's file, or a newer format, is refused.
    const detail::JsonFields f(path);
    if (doc.contains("format") && doc["format"] != "trueaxis-thermal-model")
      f.Fail("format", fmt::format("{} is not a trueaxis thermal model (expected \"trueaxis-thermal-model\")", doc["format"].dump()));
    if (doc.contains("version") && doc["version"] != 1)
      f.Fail("version", fmt::format("{}: this trueaxis reads version 1", doc["version"].dump()));
    return ThermalModelFromJson(doc["model"], path);
  }
  return ThermalModelFromJson(doc, path);
}

void WriteThermalModelFile(const ThermalErrorModel& model, const std::string& path) {
  nlohmann::json doc = {{"format", "trueaxis-thermal-model"}, {"version", 1}, {"model", model.ToJson()}};
  WriteTextFile(path, doc.dump(2) + "\n");
}

}  // namespace trueaxis::thermal
