// The fit reads no clock: the same inputs give the same model, byte for byte; the creation time is
// what the caller stamps (FitOptions::created_utc, the CLI's clock).
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::model {
namespace {

TEST(FitDeterminism, SameInputsGiveTheSameModelAndTheCallersTimeStamp) {
  testing::SyntheticMachine machine;
  const auto states = machine.MakeStates({{"cold", 0, 0, 0, 0}});
  FitOptions o;
  o.created_utc = "2026-01-02T03:04:05Z";
  const auto a = FitCompositeModel(states, o);
  const auto b = FitCompositeModel(states, o);
  EXPECT_EQ(a.model.created_utc, "2026-01-02T03:04:05Z");
  EXPECT_EQ(ModelToJson(a.model).dump(), ModelToJson(b.model).dump());
  EXPECT_EQ(FitCompositeModel(states, {}).model.created_utc, "");
}

}  // namespace
}  // namespace trueaxis::model
