// Register-level conversions: fixed-point lengths, 32-bit word order, ADAM-6015 scaling.
#include "trueaxis/drivers/register_codec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace trueaxis::drivers {
namespace {

TEST(RegisterCodec, Int32IsSplitHighWordFirst) {
  std::uint16_t r[2];
  SplitInt32(0x12345678, r);
  EXPECT_EQ(r[0], 0x1234);
  EXPECT_EQ(r[1], 0x5678);
  SplitInt32(-2, r);  // two's complement across both words
  EXPECT_EQ(r[0], 0xFFFF);
  EXPECT_EQ(r[1], 0xFFFE);
  for (std::int32_t v : {0, 1, -1, 65535, 65536, -65536, 123456789, -987654321,
                         std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::min()}) {
    SplitInt32(v, r);
    EXPECT_EQ(JoinInt32(r), v) << v;
  }
  const std::uint16_t big[2] = {0x8000, 0x0001};
  EXPECT_EQ(JoinUint32(big), 0x80000001u);
}

TEST(RegisterCodec, MicrometresRoundToTenthsOfAMicrometre) {
  std::int32_t c = 0;
  ASSERT_TRUE(MicrometresToCounts(12.34, &c));
  EXPECT_EQ(c, 123);
  ASSERT_TRUE(MicrometresToCounts(-12.36, &c));
  EXPECT_EQ(c, -124);
  ASSERT_TRUE(MicrometresToCounts(0.04, &c));
  EXPECT_EQ(c, 0);
  EXPECT_DOUBLE_EQ(CountsToMicrometres(-124), -12.4);
}

TEST(RegisterCodec, MillimetrePositionsSurviveTheTripToWithinHalfAQuantum) {
  for (double mm : {0.0, 123.4567, -455.00004, 999.99996, -0.00005, 2000.0}) {
    std::int32_t c = 0;
    ASSERT_TRUE(MillimetresToCounts(mm, &c)) << mm;
    std::uint16_t r[2];
    SplitInt32(c, r);
    EXPECT_NEAR(CountsToMillimetres(JoinInt32(r)), mm, 0.5e-4 + 1e-12) << mm;
  }
  std::int32_t c = 0;
  ASSERT_TRUE(MillimetresToCounts(123.4567, &c));
  EXPECT_EQ(c, 1234567);
}

TEST(RegisterCodec, OutOfRangeAndNanSaturateAndReportFalse) {
  std::int32_t c = 0;
  EXPECT_FALSE(MicrometresToCounts(3e11, &c));
  EXPECT_EQ(c, std::numeric_limits<std::int32_t>::max());
  EXPECT_FALSE(MicrometresToCounts(-3e11, &c));
  EXPECT_EQ(c, std::numeric_limits<std::int32_t>::min());
  EXPECT_FALSE(MicrometresToCounts(std::nan(""), &c));
  EXPECT_EQ(c, 0);
  EXPECT_FALSE(MillimetresToCounts(250000.0, &c));  // 250 m is beyond ±214.7 m
}

TEST(AdamScaling, TypeCodesOfTheAdam6015RtdRanges) {
  const auto* pt100 = FindRtdRange(0x20);
  ASSERT_NE(pt100, nullptr);
  EXPECT_EQ(pt100->min_c, -50.0);
  EXPECT_EQ(pt100->max_c, 150.0);
  const auto* pt1000 = FindRtdRange(0x2A);
  ASSERT_NE(pt1000, nullptr);
  EXPECT_EQ(pt1000->min_c, -40.0);
  EXPECT_EQ(pt1000->max_c, 160.0);
  const auto* pt100_fw5 = FindRtdRange(0x03A4);  // the same range in the 16-bit codes of firmware >= 5
  ASSERT_NE(pt100_fw5, nullptr);
  EXPECT_EQ(pt100_fw5->min_c, -50.0);
  EXPECT_EQ(pt100_fw5->max_c, 150.0);
  EXPECT_EQ(FindRtdRange(0x03A2)->min_c, -200.0);
  EXPECT_EQ(FindRtdRange(0x1F), nullptr);
  EXPECT_EQ(FindRtdRange(0x2E), nullptr);
  EXPECT_EQ(FindRtdRange(0x0000), nullptr);
}

TEST(AdamScaling, RawSpansTheRangeLinearly) {
  const auto& r = *FindRtdRange(0x20);
  EXPECT_DOUBLE_EQ(AdamRawToCelsius(0, r), -50.0);
  EXPECT_DOUBLE_EQ(AdamRawToCelsius(65535, r), 150.0);
  EXPECT_EQ(CelsiusToAdamRaw(-50.0, r), 0);
  EXPECT_EQ(CelsiusToAdamRaw(150.0, r), 65535);
  EXPECT_EQ(CelsiusToAdamRaw(50.0, r), 32768);  // 32767.5 rounds up
  EXPECT_NEAR(AdamResolutionC(r), 200.0 / 65535.0, 1e-15);
}

TEST(AdamScaling, AgreesWithAnIndependentlyWrittenReader) {
  // A published ADAM-6015 reader (slow-control code for a -200..200 °C
  // channel) converts with raw * 400 / 65535 - 200.
  const auto& r = *FindRtdRange(0x24);
  for (int raw : {0, 1, 12345, 32768, 50000, 65534}) {
    EXPECT_NEAR(AdamRawToCelsius(static_cast<std::uint16_t>(raw), r), raw * 400.0 / 65535.0 - 200.0, 1e-9) << raw;
  }
}

TEST(AdamScaling, RoundTripWithinHalfACount) {
  for (const auto& r : adam6015::kRtdRanges) {
    const double half = AdamResolutionC(r) / 2 + 1e-9;
    for (int i = 0; i <= 200; ++i) {
      const double t = r.min_c + (r.max_c - r.min_c) * i / 200.0 * 0.999;
      EXPECT_NEAR(AdamRawToCelsius(CelsiusToAdamRaw(t, r), r), t, half) << r.name << " " << t;
    }
  }
}

TEST(AdamScaling, OutsideTheRangeClampsAndOverRangeReadsAsBurnout) {
  const auto& r = *FindRtdRange(0x21);  // 0..100 °C
  EXPECT_EQ(CelsiusToAdamRaw(-10.0, r), 0);
  EXPECT_EQ(CelsiusToAdamRaw(130.0, r), adam6015::kBurnoutRaw);
  EXPECT_EQ(CelsiusToAdamRaw(std::nan(""), r), adam6015::kBurnoutRaw);
}

}  // namespace
}  // namespace trueaxis::drivers
