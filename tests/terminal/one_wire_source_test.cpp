// OneWireTemperatureSource against a fake sysfs tree: CRC errors, the 85 °C
// power-on value, a sensor that disappears and comes back, garbage files.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fake_w1_tree.hpp"
#include "support/mock_hardware.hpp"
#include "trueaxis/terminal/combined_temperature_source.hpp"
#include "trueaxis/terminal/one_wire_temperature_source.hpp"
#include "trueaxis/terminal/polled_temperature_source.hpp"

namespace trueaxis::terminal {
namespace {

using testing::FakeW1Tree;
using testing::kA;
using testing::kB;

class OneWireSourceTest : public FakeW1Tree {
 protected:
  void SetUp() override {
    FakeW1Tree::SetUp();
    Set(kA, 23125);
    Set(kB, 24500);
    source = std::make_unique<OneWireTemperatureSource>(TwoSensors());
    std::string why;
    ASSERT_TRUE(source->Configure(&why)) << why;
  }
  std::vector<hw::RawTemperature> Read() {
    std::vector<hw::RawTemperature> out(2);
    EXPECT_TRUE(source->Read(out));
    return out;
  }
  OneWireChannelStatus StatusOf(std::size_t c) { return source->StatusSnapshot().at(c); }
  static bool Good(const hw::RawTemperature& t, double c) { return !t.hardware_fault && std::abs(t.temp_c - c) < 1e-9; }
  static bool Fault(const hw::RawTemperature& t) { return t.hardware_fault && std::isnan(t.temp_c); }
  std::unique_ptr<OneWireTemperatureSource> source;
};

TEST_F(OneWireSourceTest, ReadsEachSensorUnderItsChannelName) {
  EXPECT_EQ(source->ChannelName(0), "x_nut");
  EXPECT_EQ(source->ChannelName(1), "spindle");
  const auto t = Read();
  EXPECT_TRUE(Good(t[0], 23.125));
  EXPECT_TRUE(Good(t[1], 24.5));
  Set(kA, -1250);
  EXPECT_TRUE(Good(Read()[0], -1.25));
}

TEST_F(OneWireSourceTest, ReportsTheDatasheetRangeThroughThePollerAndTheCombination) {
  EXPECT_EQ(source->ChannelMeasuringRange(1).min_c, -55.0);
  EXPECT_EQ(source->ChannelMeasuringRange(1).max_c, 125.0);
  std::vector<std::unique_ptr<hw::TemperatureSource>> parts;
  parts.push_back(std::make_unique<trueaxis::testing::MockTemperatures>(1));  // range unknown
  parts.push_back(std::make_unique<PolledTemperatureSource>(std::make_unique<OneWireTemperatureSource>(TwoSensors()), 1, 2));
  CombinedTemperatureSource combined(std::move(parts));
  EXPECT_FALSE(combined.ChannelMeasuringRange(0).known());
  EXPECT_EQ(combined.ChannelMeasuringRange(2).max_c, 125.0);
  EXPECT_FALSE(combined.ChannelMeasuringRange(3).known());  // beyond the channels
}

TEST_F(OneWireSourceTest, CrcErrorFaultsOnlyThatReadOfThatChannel) {
  Read();
  Set(kA, 99999, /*crc_ok=*/false);
  auto t = Read();
  EXPECT_TRUE(Fault(t[0]));
  EXPECT_TRUE(Good(t[1], 24.5));
  EXPECT_EQ(StatusOf(0).state, OneWireChannelState::kCrcError);
  Set(kA, 23250);
  EXPECT_TRUE(Good(Read()[0], 23.25));
  EXPECT_EQ(StatusOf(0).failed_reads, 1u);
}

TEST_F(OneWireSourceTest, PowerOnValueIsRefusedUntilTheNextReadConfirmsIt) {
  EXPECT_TRUE(Good(Read()[0], 23.125));
  Set(kA, 85000);  // sensor lost power: one 85000, then a real conversion
  EXPECT_TRUE(Fault(Read()[0]));
  EXPECT_EQ(StatusOf(0).state, OneWireChannelState::kPowerOnValue);
  Set(kA, 23187);
  EXPECT_TRUE(Good(Read()[0], 23.187));
  Set(kA, 85000);  // again, and this time it stays: confirmed by the following read
  EXPECT_TRUE(Fault(Read()[0]));
  EXPECT_TRUE(Good(Read()[0], 85.0));
  EXPECT_TRUE(Good(Read()[0], 85.0));
  EXPECT_EQ(StatusOf(0).power_on_refused, 2u);
}

TEST_F(OneWireSourceTest, PowerOnValueAfterAFailedReadStillNeedsConfirmation) {
  Set(kA, 85000);
  EXPECT_TRUE(Fault(Read()[0]));          // first read ever: refused
  Set(kA, 23000, /*crc_ok=*/false);
  EXPECT_TRUE(Fault(Read()[0]));          // CRC error in between clears the pending 85
  Set(kA, 85000);
  EXPECT_TRUE(Fault(Read()[0]));          // so this one is refused again
  EXPECT_TRUE(Good(Read()[0], 85.0));
}

TEST_F(OneWireSourceTest, A85ReadingNextToARealWarmReadingIsAccepted) {
  Set(kA, 84875);
  EXPECT_TRUE(Good(Read()[0], 84.875));
  Set(kA, 85000);  // a real temperature passing through 85 °C
  EXPECT_TRUE(Good(Read()[0], 85.0));
}

TEST_F(OneWireSourceTest, DisappearingSensorIsALostChannelThatComesBack) {
  Read();
  Remove(kB);
  auto t = Read();
  EXPECT_TRUE(Good(t[0], 23.125));
  EXPECT_TRUE(Fault(t[1]));
  EXPECT_EQ(StatusOf(1).state, OneWireChannelState::kMissing);
  Read();
  EXPECT_EQ(StatusOf(1).losses, 1u);  // one loss, however many reads it lasts
  Set(kB, 26000);
  EXPECT_TRUE(Good(Read()[1], 26.0));
  EXPECT_EQ(StatusOf(1).state, OneWireChannelState::kOk);
}

TEST_F(OneWireSourceTest, GarbageOutOfRangeAndSilentSensorsAreFaults) {
  Write(kA, "garbage\n\x01\x02");
  EXPECT_TRUE(Fault(Read()[0]));
  EXPECT_EQ(StatusOf(0).state, OneWireChannelState::kMalformed);
  Write(kA, "");
  EXPECT_TRUE(Fault(Read()[0]));
  Set(kA, 127000);
  EXPECT_TRUE(Fault(Read()[0]));
  EXPECT_EQ(StatusOf(0).state, OneWireChannelState::kOutOfRange);
  Write(kA, "00 00 00 00 00 00 00 00 00 : crc=00 YES\n00 00 00 00 00 00 00 00 00 t=0\n");
  EXPECT_TRUE(Fault(Read()[0]));
  EXPECT_EQ(StatusOf(0).state, OneWireChannelState::kNoResponse);
}

TEST_F(OneWireSourceTest, MissingBusIsALinkFaultAndLeavesTheOutputAlone) {
  std::filesystem::remove_all(root_);
  std::vector<hw::RawTemperature> out(2, hw::RawTemperature{7.0, false});
  EXPECT_FALSE(source->Read(out));
  EXPECT_EQ(out[0].temp_c, 7.0);
}

TEST_F(OneWireSourceTest, ListsSensorsOnTheBusThatNoChannelNames) {
  Set("28-000000000001", 20000);
  EXPECT_EQ(source->UnmappedSensors(), std::vector<std::string>{"28-000000000001"});
}

TEST(OneWireOptions, RefusesDuplicatesAndPaths) {
  OneWireOptions o;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  o.sensors = {{"28-0316a2794aff", "a"}, {"28-0316a2794aff", "b"}};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("twice"), std::string::npos);
  o.sensors = {{"../etc", "a"}};
  EXPECT_FALSE(o.IsValid(&why));
  o.sensors = {{"28-0316a2794aff", "a"}, {"28-0416b1c2d3e4", "a"}};
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace trueaxis::terminal
