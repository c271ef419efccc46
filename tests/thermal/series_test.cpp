#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "support/shared_data.hpp"

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/series_cleaning.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::thermal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ThermalSeriesCsv, ParsesColumnsByNameAndMissingValues) {
  const std::string text =
      "# machine: VMC-1\n"
      "time_s,spindle_rpm,coolant,t_spindle_c,t7_C,e_z_um,ch2_um\n"
      "0,0,off,20.5,21,1.5,2\n"
      "15,1000,flood,,21.1,nan,2.5\n";
  ThermalSeries s = ParseThermalSeriesCsv(text, "x.csv");
  EXPECT_EQ(s.metadata.at("machine"), "VMC-1");
  ASSERT_EQ(s.Rows(), 2);
  EXPECT_EQ(s.temperature_names, (std::vector<std::string>{"spindle", "t7"}));
  EXPECT_EQ(s.error_names, (std::vector<std::string>{"z", "ch2"}));
  EXPECT_TRUE(std::isnan(s.temperatures_c(1, 0)));
  EXPECT_TRUE(std::isnan(s.errors_um(1, 0)));
  EXPECT_DOUBLE_EQ(s.spindle_rpm[1], 1000);
  EXPECT_EQ(s.coolant[1], CoolantState::kFlood);
  EXPECT_EQ(s.source_line[1], 4);
}

TEST(ThermalSeriesCsv, RoundTripsLosslessly) {
  std::mt19937_64 rng(3);
  ThermalSeries s = testing::MakeSeries(50, 3);
  for (int c = 0; c < 3; ++c) s.temperatures_c.col(c) = testing::RandomWalk(rng, 50, 20 + c, 0.01);
  s.errors_um.col(0) = s.temperatures_c.col(0) * 3.3;
  s.temperatures_c(7, 1) = kNaN;
  s.has_position = true;
  s.position_mm.assign(50, -12.25);
  s.metadata["axis"] = "Z";
  ThermalSeries back = ParseThermalSeriesCsv(FormatThermalSeriesCsv(s), "rt");
  EXPECT_EQ(back.temperature_names, s.temperature_names);
  EXPECT_EQ(back.time_s, s.time_s);
  EXPECT_EQ(back.position_mm, s.position_mm);
  EXPECT_TRUE(std::isnan(back.temperatures_c(7, 1)));
  back.temperatures_c(7, 1) = s.temperatures_c(7, 1) = 0;
  EXPECT_EQ(back.temperatures_c, s.temperatures_c);  // exact: shortest round-trip text
  EXPECT_EQ(back.errors_um, s.errors_um);
  EXPECT_EQ(back.metadata.at("axis"), "Z");
}

void ExpectError(const std::string& text, int line, const std::string& field) {
  try {
    ParseThermalSeriesCsv(text, "bad.csv");
    FAIL() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "bad.csv");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(ThermalSeriesCsv, BadInputNamesLineAndField) {
  ExpectError("time_s,t_a_c,e_x_um\n0,20,1\n15,warm,1\n", 3, "t_a_c");
  ExpectError("time_s,t_a_c,e_x_um\n0,20,1\n0,20,1\n", 3, "time_s");      // not increasing
  ExpectError("time_s,t_a_c,e_x_um\n0,20,1\n15,20\n", 3, "");             // field count
  ExpectError("time_s,t_a_c,speed,e_x_um\n", 1, "speed");                 // unknown column
  ExpectError("time_s,t_a_c,e_x_um\n0,20,1um\n", 2, "e_x_um");
  ExpectError("time_s,t_a_c,e_x_um\n0,900,1\n", 2, "t_a_c");              // implausible °C
  ExpectError("time_s,t_a_c,e_x_um\n0,20,1\n15,20,1e15\n", 3, "e_x_um");  // 1e15 µm: coefficients near 1e296
  ExpectError("time_s,t_a_c,e_x_um\n0,293.5,1\n", 1, "t_a_c");            // kelvin: the column, at its header
  ExpectError("time_s,t_a_c,e_x_um\n1e300,20,1\n", 2, "time_s");
  ExpectError("time_s,spindle_rpm,t_a_c,e_x_um\n0,-5,20,1\n", 2, "spindle_rpm");
  ExpectError("# only a comment\n", 0, "");
}

TEST(FlThermal, ImportsAllRowsAndColumns) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(std::string(TRUEAXIS_SHARED_DATA_DIR) + "/fl_thermal/fl_thermal.csv");
  ThermalSeries s = ImportFlThermalCsv(std::string(TRUEAXIS_SHARED_DATA_DIR) + "/fl_thermal/fl_thermal.csv");
  EXPECT_EQ(s.Rows(), 11115);
  EXPECT_EQ(s.temperature_names.size(), 16u);
  EXPECT_EQ(s.error_names.size(), 5u);
  EXPECT_EQ(s.temperature_names.front(), "t1");
  EXPECT_EQ(s.error_names.back(), "ch5");
  EXPECT_FALSE(s.temperatures_c.hasNaN());
  EXPECT_DOUBLE_EQ(s.time_s.back(), 166710.0);
  auto blocks = SpeedBlocks(s);
  ASSERT_EQ(blocks.size(), 16u);  // 0,1250,0,2500,0,3750,0,5000,0,3500,0,500,1500,2500,4500,0
  EXPECT_DOUBLE_EQ(blocks[7].spindle_rpm, 5000);
  EXPECT_DOUBLE_EQ(blocks[9].spindle_rpm, 3500);
  EXPECT_DOUBLE_EQ(blocks[14].spindle_rpm, 4500);
  EXPECT_EQ(blocks[1].last_row - blocks[1].first_row + 1, 960);  // 4 h at 15 s
}

TEST(FlThermal, RefusesAFileWithADifferentLayout) {
  const std::string dir = testing::TempDir("fl");
  const std::string path = dir + "/other.csv";
  FILE* f = fopen(path.c_str(), "w");
  fputs("time_s,spindle_rpm,t1_C,ch1_um\n0,0,20,1\n", f);
  fclose(f);
  EXPECT_THROW(ImportFlThermalCsv(path), InputError);
}

ThermalSeries CleanFixture() {
  std::mt19937_64 rng(5);
  ThermalSeries s = testing::MakeSeries(200, 3);
  for (int c = 0; c < 3; ++c) s.temperatures_c.col(c) = testing::RandomWalk(rng, 200, 20, 0.01);
  s.errors_um.col(0) = 2.0 * s.temperatures_c.col(0);
  return s;
}

TEST(SeriesCleaning, InterpolatesShortGapsLinearly) {
  ThermalSeries s = CleanFixture();
  const double before = s.temperatures_c(49, 1), after = s.temperatures_c(53, 1);
  for (int r = 50; r <= 52; ++r) s.temperatures_c(r, 1) = kNaN;
  s.errors_um(100, 0) = kNaN;
  SeriesCleaningReport rep;
  ThermalSeries c = CleanSeries(s, {}, &rep);
  EXPECT_EQ(rep.interpolated_values, 4);
  EXPECT_TRUE(rep.dropped_temperatures.empty());
  EXPECT_NEAR(c.temperatures_c(51, 1), (before + after) / 2, 1e-12);
  EXPECT_NEAR(c.errors_um(100, 0), (s.errors_um(99, 0) + s.errors_um(101, 0)) / 2, 1e-12);
}

TEST(SeriesCleaning, DropsASensorThatDiesHalfWayWithAWarning) {
  ThermalSeries s = CleanFixture();
  for (int r = 100; r < 200; ++r) s.temperatures_c(r, 2) = kNaN;
  SeriesCleaningReport rep;
  ThermalSeries c = CleanSeries(s, {}, &rep);
  EXPECT_EQ(c.temperature_names, (std::vector<std::string>{"s0", "s1"}));
  EXPECT_EQ(rep.dropped_temperatures, (std::vector<std::string>{"s2"}));
  ASSERT_EQ(rep.warnings.size(), 1u);
  EXPECT_NE(rep.warnings[0].find("died"), std::string::npos) << rep.warnings[0];
  // strict: refused, naming the line where it stopped
  SeriesCleaningOptions strict;
  strict.drop_bad_temperature_channels = false;
  try {
    CleanSeries(s, strict, nullptr);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "s2");
    EXPECT_EQ(e.line(), s.source_line[100]);
  }
}

TEST(SeriesCleaning, DropsLongInteriorGapsAndConstantChannels) {
  ThermalSeries s = CleanFixture();
  for (int r = 20; r < 40; ++r) s.temperatures_c(r, 1) = kNaN;  // 20 > 4
  s.temperatures_c.col(2).setConstant(21.0);
  SeriesCleaningReport rep;
  ThermalSeries c = CleanSeries(s, {}, &rep);
  EXPECT_EQ(c.temperature_names, (std::vector<std::string>{"s0"}));
  EXPECT_EQ(rep.dropped_temperatures.size(), 2u);
}

TEST(SeriesCleaning, RefusesErrorGapsTimeGapsAndNoTemperatureLeft) {
  {
    ThermalSeries s = CleanFixture();
    for (int r = 60; r < 70; ++r) s.errors_um(r, 0) = kNaN;
    try {
      CleanSeries(s, {}, nullptr);
      FAIL();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "e");
      EXPECT_EQ(e.line(), s.source_line[60]);
    }
  }
  {
    ThermalSeries s = CleanFixture();
    for (std::size_t r = 120; r < s.time_s.size(); ++r) s.time_s[r] += 3600;
    try {
      CleanSeries(s, {}, nullptr);
      FAIL();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "time_s");
      EXPECT_EQ(e.line(), s.source_line[120]);
    }
    SeriesCleaningOptions allow;
    allow.allow_time_gaps = true;
    SeriesCleaningReport rep;
    EXPECT_NO_THROW(CleanSeries(s, allow, &rep));
    EXPECT_EQ(rep.warnings.size(), 1u);
  }
  {
    ThermalSeries s = CleanFixture();
    s.temperatures_c.col(0).setConstant(kNaN);
    s.temperatures_c.col(1).setConstant(kNaN);
    for (int r = 10; r < 200; ++r) s.temperatures_c(r, 2) = kNaN;
    EXPECT_THROW(CleanSeries(s, {}, nullptr), InputError);
  }
}

TEST(SeriesCleaning, ASeriesWithoutErrorsIsForPredictionOnly) {
  ThermalSeries s = ParseThermalSeriesCsv("time_s,t_a_c\n0,20\n15,20.5\n30,21\n", "p.csv");
  EXPECT_TRUE(s.error_names.empty());
  EXPECT_THROW(CleanSeries(s, {}, nullptr), InputError);
  SeriesCleaningOptions predict_only;
  predict_only.check_error_channels = false;
  EXPECT_EQ(CleanSeries(s, predict_only, nullptr).Rows(), 3);
}

TEST(SeriesCleaning, KeepsAllConstantTemperaturesOfAOneTemperatureTable) {
  ThermalSeries s = ReadThermalSeriesCsv(std::string(TRUEAXIS_SOURCE_DIR) + "/data/thermal/seed003_z_axis.csv");
  EXPECT_FALSE(s.has_time);
  SeriesCleaningReport rep;
  ThermalSeries c = CleanSeries(s, {}, &rep);
  EXPECT_EQ(c.temperature_names, (std::vector<std::string>{"z"}));
  EXPECT_EQ(rep.warnings.size(), 1u);
}

}  // namespace
}  // namespace trueaxis::thermal
