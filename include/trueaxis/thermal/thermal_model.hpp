#pragma once
// One interface for every data-driven thermal error model, so the runtime and
// the server can use any of them (docs/thermal-models.md).
//
// A model predicts every error channel it was fitted on from one sample: the
// temperatures of its own input sensors (in InputSensors() order), the axis
// position (models with UsesPosition()) and the heating/steady/cooling
// interval (models with UsesInterval(); the interval comes from the trend of
// the temperature, see hysteresis_model.hpp). Predict is const, pure and
// allocation-free. Sign: prediction = the error (actual - commanded, µm);
// the correction to apply is its negative (docs/sign-convention.md).
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

// kStartUp: too little history to tell (the trend window is not yet half filled, at the start of a
// recording or after a gap); a hysteresis model predicts it with its all-data model, which was
// trained on every state, never with a sub-model trained on another interval.
enum class ThermalInterval { kHeating = 0, kSteady = 1, kCooling = 2, kStartUp = 3 };
inline constexpr int kThermalIntervalCount = 3;  // intervals with a sub-model of their own
const char* ThermalIntervalName(ThermalInterval i);

struct ThermalSample {
  std::span<const double> temperatures_c;  // model.InputSensors() order
  double position_mm = 0.0;
  ThermalInterval interval = ThermalInterval::kSteady;
};

class ThermalErrorModel {
 public:
  virtual ~ThermalErrorModel() = default;
  virtual std::string_view Kind() const = 0;
  virtual const std::vector<std::string>& InputSensors() const = 0;
  virtual const std::vector<std::string>& Channels() const = 0;
  virtual bool UsesPosition() const { return false; }
  virtual bool UsesInterval() const { return false; }
  // out_um.size() == Channels().size().
  virtual void Predict(const ThermalSample& sample, std::span<double> out_um) const = 0;
  // Interval of every row of a series, as this model classifies it (all
  // kSteady for models that do not use intervals).
  virtual std::vector<ThermalInterval> ClassifyRows(const ThermalSeries& series) const;
  virtual nlohmann::json ToJson() const = 0;  // includes "kind"
  // One line per channel: inputs and coefficients / structure.
  virtual std::string Describe() const = 0;
};

// Predictions for every row of a series (rows x Channels()). The series must
// hold the model's input sensors by name (InputError naming the sensor
// otherwise) and a position column when the model uses position.
Eigen::MatrixXd PredictSeries(const ThermalErrorModel& model, const ThermalSeries& series);

std::unique_ptr<ThermalErrorModel> ThermalModelFromJson(const nlohmann::json& doc, const std::string& source);
std::unique_ptr<ThermalErrorModel> ReadThermalModelFile(const std::string& path);
void WriteThermalModelFile(const ThermalErrorModel& model, const std::string& path);

}  // namespace trueaxis::thermal
