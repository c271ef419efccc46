#include "trueaxis/signal/conversions.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace trueaxis::signal {
namespace {

TEST(AnalogConversion, SeedChainEndpointsAndMidScale) {
  const AnalogChannelOptions o;  // 0-50 °C -> 0-5 V -> 12 bit over 0-5 V
  EXPECT_DOUBLE_EQ(AdcCountToVolts(0, o), 0.0);
  EXPECT_DOUBLE_EQ(AdcCountToVolts(4095, o), 5.0);
  EXPECT_DOUBLE_EQ(TransmitterVoltsToCelsius(2.5, o), 25.0);
  EXPECT_DOUBLE_EQ(CelsiusToTransmitterVolts(20.0, o), 2.0);
  EXPECT_NEAR(ConvertAdcCount(2048, o).temp_c, 2048 * 50.0 / 4095, 1e-12);
  EXPECT_NEAR(AnalogResolutionC(o), 50.0 / 4095, 1e-12);  // 0.0122 °C per count
}

TEST(AnalogConversion, EveryCountRoundTripsAndQuantisationIsHalfAStep) {
  const AnalogChannelOptions o;
  for (int count = 0; count <= o.FullScaleCount(); ++count) {
    const double c = ConvertAdcCount(count, o).temp_c;
    ASSERT_EQ(VoltsToAdcCount(CelsiusToTransmitterVolts(c, o), o), count);
  }
  const double step = AnalogResolutionC(o);
  for (double t = 0.1; t < 49.9; t += 0.0371) {
    const int count = VoltsToAdcCount(CelsiusToTransmitterVolts(t, o), o);
    ASSERT_LE(std::abs(ConvertAdcCount(count, o).temp_c - t), 0.5 * step + 1e-12) << t;
  }
}

TEST(AnalogConversion, RailsAndOutOfSpanAreFaults) {
  AnalogChannelOptions o;
  EXPECT_EQ(ConvertAdcCount(0, o).condition, ConversionCondition::kAtAdcRail);
  EXPECT_EQ(ConvertAdcCount(4095, o).condition, ConversionCondition::kAtAdcRail);
  EXPECT_TRUE(ConvertAdcCount(4095, o).ToRaw().hardware_fault);
  EXPECT_EQ(ConvertAdcCount(4096, o).condition, ConversionCondition::kInvalid);
  EXPECT_EQ(ConvertAdcCount(-1, o).condition, ConversionCondition::kInvalid);
  EXPECT_EQ(ConvertAdcCount(1000, o).condition, ConversionCondition::kOk);
  EXPECT_FALSE(ConvertAdcCount(1000, o).ToRaw().hardware_fault);
  // A bipolar ±10 V card sees beyond the transmitter span: open RTD drives
  // an up-scale transmitter above 5 V, a short reads below 0 V.
  o.adc_min_v = -10;
  o.adc_max_v = 10;
  EXPECT_EQ(ConvertAdcCount(VoltsToAdcCount(5.5, o), o).condition, ConversionCondition::kAboveSpan);
  EXPECT_EQ(ConvertAdcCount(VoltsToAdcCount(-0.5, o), o).condition, ConversionCondition::kBelowSpan);
  EXPECT_EQ(ConvertAdcCount(VoltsToAdcCount(5.05, o), o).condition, ConversionCondition::kOk);  // inside the 1 °C margin
  EXPECT_NEAR(ConvertAdcCount(VoltsToAdcCount(2.5, o), o).temp_c, 25.0, 0.5 * AnalogResolutionC(o) + 1e-9);
}

TEST(AnalogConversion, OtherRangesViaOptions) {
  AnalogChannelOptions o;
  o.span_min_c = -50;
  o.span_max_c = 150;
  o.span_min_v = 0;
  o.span_max_v = 10;
  o.adc_max_v = 10;
  o.adc_bits = 16;
  EXPECT_DOUBLE_EQ(TransmitterVoltsToCelsius(2.5, o), 0.0);
  EXPECT_DOUBLE_EQ(TransmitterVoltsToCelsius(10, o), 150.0);
  EXPECT_NEAR(AnalogResolutionC(o), 200.0 / 65535, 1e-12);
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.adc_bits = 40;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("adc_bits"), std::string::npos);
  o = {};
  o.span_max_c = o.span_min_c;
  EXPECT_FALSE(o.IsValid(&why));
}

// Datasheet table "Temperature/Data Relationship" of the DS18B20.
TEST(Ds18b20Conversion, DatasheetTable) {
  struct Row {
    std::uint16_t raw;
    double temp_c;
  } rows[] = {{0x07D0, 125.0},   {0x0550, 85.0},    {0x0191, 25.0625}, {0x00A2, 10.125},  {0x0008, 0.5},
              {0x0000, 0.0},     {0xFFF8, -0.5},    {0xFF5E, -10.125}, {0xFE6F, -25.0625}, {0xFC90, -55.0}};
  for (const auto& r : rows) {
    EXPECT_DOUBLE_EQ(Ds18b20RawToCelsius(r.raw), r.temp_c) << std::hex << r.raw;
    EXPECT_EQ(CelsiusToDs18b20Raw(r.temp_c), r.raw) << r.temp_c;
  }
}

TEST(Ds18b20Conversion, QuantisesToSixteenthsAndMasksLowResolution) {
  for (double t = -20; t < 60; t += 0.013) {
    const double q = Ds18b20RawToCelsius(CelsiusToDs18b20Raw(t));
    ASSERT_LE(std::abs(q - t), kDs18b20LsbC / 2 + 1e-12);
    ASSERT_DOUBLE_EQ(q * 16, std::round(q * 16));
  }
  Ds18b20Options nine;
  nine.resolution_bits = 9;  // 0.5 °C steps: three undefined low bits
  EXPECT_DOUBLE_EQ(Ds18b20RawToCelsius(0x0191, nine), 25.0);
  EXPECT_DOUBLE_EQ(Ds18b20RawToCelsius(0x0197, nine), 25.0);
  EXPECT_EQ(CelsiusToDs18b20Raw(25.2, nine), 0x0190);
  EXPECT_EQ(CelsiusToDs18b20Raw(25.3, nine), 0x0198);
  EXPECT_FALSE(Ds18b20Options{8}.IsValid(nullptr));
}

TEST(Ds18b20Conversion, PowerOnValueIsSuspiciousAndOutOfRangeIsInvalid) {
  EXPECT_EQ(ConvertDs18b20(0x0550).condition, ConversionCondition::kSuspicious);
  EXPECT_TRUE(ConvertDs18b20(0x0550).ToRaw().hardware_fault);
  EXPECT_EQ(ConvertDs18b20(0x0551).condition, ConversionCondition::kOk);  // 85.0625 is a real reading
  Ds18b20Options allow;
  allow.power_on_value_is_fault = false;
  EXPECT_EQ(ConvertDs18b20(0x0550, allow).condition, ConversionCondition::kOk);
  EXPECT_EQ(ConvertDs18b20(0x07D1).condition, ConversionCondition::kInvalid);  // > 125 °C
  EXPECT_EQ(ConvertDs18b20(0xFC8F).condition, ConversionCondition::kInvalid);  // < -55 °C
  EXPECT_EQ(ConvertDs18b20(0x0191).condition, ConversionCondition::kOk);
  EXPECT_EQ(ConversionConditionName(ConversionCondition::kSuspicious), "suspicious");
}

}  // namespace
}  // namespace trueaxis::signal
