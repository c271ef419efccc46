// A geometric-only model (fitted from cold runs: no key sensors, no ρ term) runs on a machine
// without temperature channels, even when it records the room sensor of its measurement; a model
// that computes with a sensor the machine does not map is refused, saying which sensor, which
// axis and how to map it — never run as a geometric-only one.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/hw/no_temperature_source.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::TestAxisModel;

// What `trueaxis fit` writes for a cold measurement with a t_air_c column and no cte metadata:
// the room sensor recorded, ρ = 0, no thermal part.
std::shared_ptr<const model::CompositeModel> ColdFitModel(double rho_um_per_mm_per_c = 0) {
  model::AxisModel a = TestAxisModel("X");
  a.key_sensors.clear();
  a.baseline_temp_c.clear();
  for (auto& d : a.directions) d.thermal.clear();
  a.ambient_sensor = "air";
  a.ambient_baseline_c = 20;
  a.rho_um_per_mm_per_c = rho_um_per_mm_per_c;
  a.key_rise_above_ambient = true;
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(a);
  return m;
}

CompensatorOptions Fast() {
  CompensatorOptions o;
  o.shaper.max_step_um = 1000;
  o.shaper.max_correction_um = 500;
  return o;
}

std::string PublishError(const std::shared_ptr<const model::CompositeModel>& m) {
  MockCnc cnc({"X"});
  hw::NoTemperatureSource no_channels;
  signal::MonitoredTemperatureSource none(no_channels);  // judged, as station::OpenMachine does
  auto comp = Compensator::ForHardware(Fast(), cnc, none, {});
  try {
    comp->PublishModel(m, "model.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GeometricOnlyModel, RunsWithoutTemperatureChannels) {
  const auto m = ColdFitModel();
  EXPECT_FALSE(m->axes[0].AmbientInUse());
  MockCnc cnc({"X"});
  hw::NoTemperatureSource no_channels;
  signal::MonitoredTemperatureSource none(no_channels);  // judged, as station::OpenMachine does
  auto comp = Compensator::ForHardware(Fast(), cnc, none, {});
  comp->PublishModel(m, "model.json");  // no "air" channel: not needed
  cnc.axes[0] = {400, +1, true};
  const CycleStatus* s = nullptr;
  for (int i = 0; i < 3; ++i) s = &comp->RunCycle(cnc, none, 0.01 * (i + 1));
  EXPECT_EQ(s->alarms, 0u) << AlarmNames(s->alarms);
  model::ThermalState cold{{}, std::nan(""), CoolantState::kOff, false};
  const double geometric = model::CorrectionUm(model::Predict(m->axes[0], 400, Direction::kForward, cold));
  EXPECT_GT(std::fabs(geometric), 3);
  EXPECT_DOUBLE_EQ(s->axes[0].desired_um, geometric);
  EXPECT_NEAR(cnc.cnc_value_um[0], geometric, 0.75 + 1e-9);
}

TEST(GeometricOnlyModel, ARoomTermNeedsItsSensorAndSaysHowToMapIt) {
  const auto m = ColdFitModel(-0.0115);  // ρ from the cold file's cte: a thermal (room) term
  EXPECT_TRUE(m->axes[0].AmbientInUse());
  const std::string e = PublishError(m);
  EXPECT_NE(e.find("model.json"), std::string::npos) << e;
  EXPECT_NE(e.find("axes[X].ambient_sensor"), std::string::npos) << e;
  EXPECT_NE(e.find("axis X's model"), std::string::npos) << e;
  EXPECT_NE(e.find("'air'"), std::string::npos) << e;
  EXPECT_NE(e.find("[channels] air = "), std::string::npos) << e;
  EXPECT_NE(e.find("--ambient-sensor none"), std::string::npos) << e;
}

TEST(GeometricOnlyModel, AThermalModelIsNeverRunWithoutItsKeySensors) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));  // keys nut, bearing; room sensor "ambient"
  const std::string e = PublishError(m);
  EXPECT_NE(e.find("axes[X].key_sensors"), std::string::npos) << e;
  EXPECT_NE(e.find("axis X's model needs the key sensor 'nut'"), std::string::npos) << e;
  EXPECT_NE(e.find("[channels] nut = "), std::string::npos) << e;
}

}  // namespace
}  // namespace trueaxis::runtime
