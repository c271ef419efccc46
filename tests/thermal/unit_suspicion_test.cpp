// The recording-level unit rules (core/plausibility.hpp) the thermal reader applies: where each
// one starts to suspect another unit, and what it names.
#include <gtest/gtest.h>

#include "trueaxis/core/plausibility.hpp"

namespace trueaxis {
namespace {

TEST(UnitSuspicion, TemperaturesByTheCoolestSensor) {
  EXPECT_FALSE(SuspectTemperatureUnit(21.0));   // a shop
  EXPECT_FALSE(SuspectTemperatureUnit(38.0));   // a tropical shop
  EXPECT_FALSE(SuspectTemperatureUnit(45.0));
  EXPECT_EQ(SuspectTemperatureUnit(50.0).unit, SuspectedUnit::kFahrenheit);  // 10 °C
  EXPECT_EQ(SuspectTemperatureUnit(70.0).unit, SuspectedUnit::kFahrenheit);
  EXPECT_NE(SuspectTemperatureUnit(69.8).why.find("21.0 °C if it is °F"), std::string::npos);
  EXPECT_EQ(SuspectTemperatureUnit(294.15).unit, SuspectedUnit::kKelvin);
  EXPECT_NE(SuspectTemperatureUnit(294.15).why.find("21.0 °C if it is kelvin"), std::string::npos);
  EXPECT_FALSE(SuspectTemperatureUnit(180.0));  // no unit makes it a machine: refused per value
  EXPECT_FALSE(SuspectTemperatureUnit(900.0));
}

TEST(UnitSuspicion, ErrorsThatReadLikeMillimetres) {
  EXPECT_EQ(SuspectErrorUnit(0.016, 0.010).unit, SuspectedUnit::kMillimetre);  // a 16 µm drift in mm
  EXPECT_FALSE(SuspectErrorUnit(0.0, 0.0));     // all zero: a constant channel, said elsewhere
  EXPECT_FALSE(SuspectErrorUnit(0.5, 0.03));    // beyond ±0.2: µm
  EXPECT_FALSE(SuspectErrorUnit(0.15, 0.06));   // RMS of 0.06: µm
  EXPECT_FALSE(SuspectErrorUnit(16.0, 8.0));
}

TEST(UnitSuspicion, TimeThatReadsLikeMinutes) {
  EXPECT_FALSE(SuspectTimeUnit(8.0, 6 * 3600.0));  // 8 °C in 6 h
  EXPECT_FALSE(SuspectTimeUnit(1.0, 60.0));        // exactly 60 °C/h
  EXPECT_EQ(SuspectTimeUnit(8.0, 360.0).unit, SuspectedUnit::kMinutes);  // 8 °C in "360 s"
  EXPECT_FALSE(SuspectTimeUnit(8.0, 0.0));
}

}  // namespace
}  // namespace trueaxis
