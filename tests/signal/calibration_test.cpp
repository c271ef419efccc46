#include "trueaxis/signal/calibration.hpp"

#include <cmath>
#include <filesystem>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::signal {
namespace {

namespace fs = std::filesystem;

// A session at several plateaus (20, 25, 30, 35, 40 °C), 60 readings each.
// Sensor i reads (reference - offset_i) / gain_i + noise, so the calibration
// must come back with gain_i and offset_i.
struct Session {
  std::vector<double> reference;
  std::vector<std::vector<double>> sensors;
};
Session MakeSession(const std::vector<std::pair<double, double>>& gain_offset, double noise = 0.02) {
  Session s;
  s.sensors.resize(gain_offset.size());
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, noise);
  for (double plateau : {20.0, 25.0, 30.0, 35.0, 40.0}) {
    for (int k = 0; k < 60; ++k) {
      const double ref = plateau + 0.05 * std::sin(k);
      s.reference.push_back(ref + n(rng) * 0.25);
      for (std::size_t i = 0; i < gain_offset.size(); ++i)
        s.sensors[i].push_back((ref - gain_offset[i].second) / gain_offset[i].first + n(rng));
    }
  }
  return s;
}

TEST(FitCalibration, RecoversKnownOffsetAndGain) {
  const auto s = MakeSession({{1.015, -0.35}, {0.985, 0.6}, {1.0, 0.0}});
  const double expected[][2] = {{1.015, -0.35}, {0.985, 0.6}, {1.0, 0.0}};
  for (int i = 0; i < 3; ++i) {
    const auto fit = FitCalibration(s.sensors[i], s.reference);
    EXPECT_TRUE(fit.gain_fitted);
    EXPECT_NEAR(fit.calibration.gain, expected[i][0], 0.001) << i;
    EXPECT_NEAR(fit.calibration.offset_c, expected[i][1], 0.03) << i;
    EXPECT_EQ(fit.points, 300);
    EXPECT_LT(fit.rms_residual_c, 0.03);
    EXPECT_NEAR(fit.reference_span_c, 20.1, 0.1);
    // Exact data gives the exact answer.
  }
  std::vector<double> x = {20, 30, 40}, y;
  for (double v : x) y.push_back(1.01 * v - 0.25);
  const auto exact = FitCalibration(x, y);
  EXPECT_NEAR(exact.calibration.gain, 1.01, 1e-12);
  EXPECT_NEAR(exact.calibration.offset_c, -0.25, 1e-10);
  EXPECT_NEAR(exact.max_abs_residual_c, 0, 1e-10);
  EXPECT_NEAR(exact.max_abs_error_before_c, 0.15, 1e-10);
  EXPECT_NE(exact.BriefReport().find("gain 1.01000"), std::string::npos);
}

TEST(FitCalibration, SmallSpanFitsOffsetOnly) {
  std::vector<double> x = {22.0, 22.1, 22.3, 22.2}, y;
  for (double v : x) y.push_back(v + 0.4);
  const auto fit = FitCalibration(x, y);
  EXPECT_FALSE(fit.gain_fitted);
  EXPECT_DOUBLE_EQ(fit.calibration.gain, 1.0);
  EXPECT_NEAR(fit.calibration.offset_c, 0.4, 1e-12);
  EXPECT_NE(fit.BriefReport().find("span too small"), std::string::npos);
}

TEST(FitCalibration, RejectsImplausibleOrInsufficientData) {
  std::vector<double> x = {20, 30, 40}, y = {20, 45, 70};  // gain 2.5: wrong sensor type/scaling
  EXPECT_THROW(FitCalibration(x, y), std::invalid_argument);
  std::vector<double> two = {20, 30};
  EXPECT_THROW(FitCalibration(two, two), std::invalid_argument);
  std::vector<double> with_nan = {20, NAN, 30, 40}, ref = {20, 25, 30, NAN};
  EXPECT_THROW(FitCalibration(with_nan, ref), std::invalid_argument);  // only 2 complete pairs
  std::vector<double> three = {1, 2, 3};
  EXPECT_THROW(FitCalibration(three, two), std::invalid_argument);
}

TEST(CalibrationSession, ParsesAndCalibratesAndRoundTripsThroughJson) {
  const std::string csv =
      "# calibration block, 2026-11-20\n"
      "time_s,ref,t_x_nut_c,x_bearing\n"
      "0,20.0,19.6,20.5\n"
      "60,25.0,24.5,\n"
      "120,30.0,29.4,30.5\n"
      "180,35.0,34.3,35.5\n";
  const auto session = ParseCalibrationSessionCsv(csv, "cal.csv");
  ASSERT_EQ(session.sensors.size(), 3u);
  EXPECT_EQ(session.sensors[1], "x_nut");
  EXPECT_EQ(session.rows(), 4u);
  EXPECT_TRUE(std::isnan(session.readings_c[2][1]));
  const auto set = CalibrateSession(session, "ref");
  ASSERT_EQ(set.sensors.size(), 2u);
  EXPECT_NEAR(set.sensors.at("x_bearing").calibration.offset_c, -0.5, 1e-9);
  EXPECT_EQ(set.sensors.at("x_bearing").points, 3);
  const auto& nut = set.sensors.at("x_nut").calibration;
  EXPECT_NEAR(nut.Apply(29.4), 30.0, 0.05);
  const auto back = CalibrationSetFromJson(CalibrationSetToJson(set), "mem.json");
  EXPECT_EQ(back.reference, "ref");
  EXPECT_DOUBLE_EQ(back.sensors.at("x_nut").calibration.gain, nut.gain);
  EXPECT_DOUBLE_EQ(back.sensors.at("x_nut").calibration.offset_c, nut.offset_c);
  EXPECT_NE(set.FullReport().find("x_bearing"), std::string::npos);
}

TEST(CalibrationSession, BadInputNamesFileLineAndField) {
  try {
    ParseCalibrationSessionCsv("ref,a\n20,20\n25,abc\n", "s.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "a");
    EXPECT_NE(std::string(e.what()).find("s.csv:3"), std::string::npos);
  }
  EXPECT_THROW(ParseCalibrationSessionCsv("ref,a\n20,20,1\n", "s.csv"), InputError);
  EXPECT_THROW(ParseCalibrationSessionCsv("ref,ref\n20,20\n", "s.csv"), InputError);
  EXPECT_THROW(ParseCalibrationSessionCsv("ref\n20\n", "s.csv"), InputError);
  EXPECT_THROW(ParseCalibrationSessionCsv("", "s.csv"), InputError);
  EXPECT_THROW(ParseCalibrationSessionCsv("ref,a\n", "s.csv"), InputError);
  EXPECT_THROW(ParseCalibrationSessionCsv("ref,a\n20,9999\n", "s.csv"), InputError);
  const auto session = ParseCalibrationSessionCsv("ref,a\n20,20\n30,31\n40,41\n", "s.csv");
  try {
    CalibrateSession(session, "reference");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "reference");
    EXPECT_NE(e.message().find("ref, a"), std::string::npos);
  }
}

// A column that stays put while its partner moves over min_span_c or more was not at the partner's
// temperature: an offset-only "calibration" of it was written (offset +13 °C, residual rms 6 °C, exit 0).
TEST(CalibrationSession, RefusesAStuckSensorOrAStuckReferenceNamingTheColumn) {
  std::string stuck_sensor = "ref,x_nut,x_bearing\n", stuck_reference = "ref,x_nut,x_bearing\n";
  for (int i = 0; i <= 20; ++i) {
    const double t = 20.0 + i;
    stuck_sensor += fmt::format("{},20.0,{}\n", t, t + 0.1);
    stuck_reference += fmt::format("22.5,{},{}\n", t, t + 0.1);
  }
  try {
    CalibrateSession(ParseCalibrationSessionCsv(stuck_sensor, "s.csv"), "ref");
    FAIL() << "a stuck sensor was calibrated";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "s.csv");
    EXPECT_EQ(e.field(), "x_nut");
    EXPECT_NE(e.message().find("sensor 'x_nut' spans 0.00 °C while reference 'ref' spans 20.00 °C"), std::string::npos)
        << e.message();
  }
  try {
    CalibrateSession(ParseCalibrationSessionCsv(stuck_reference, "s.csv"), "ref");
    FAIL() << "a stuck reference was used";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "ref");
    EXPECT_NE(e.message().find("reference 'ref' spans 0.00 °C"), std::string::npos) << e.message();
  }
  // One temperature for all (a block at one plateau): offset only, as before, and said consistently.
  const auto one_plateau = CalibrateSession(ParseCalibrationSessionCsv("ref,a\n20,20.4\n20.1,20.5\n20.05,20.45\n", "s.csv"), "ref");
  EXPECT_FALSE(one_plateau.sensors.at("a").gain_fitted);
  EXPECT_NE(one_plateau.FullReport().find("(not fitted: reference span too small)"), std::string::npos);
  EXPECT_NE(one_plateau.FullReport().find("reference span 0.10 °C"), std::string::npos) << one_plateau.FullReport();
}

TEST(CalibrationSession, EmptyColumnNameNamesLineAndHeader) {
  try {
    ParseCalibrationSessionCsv("# block\nref,,a\n20,20,20\n", "s.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "header");
    EXPECT_NE(e.message().find("column 2 of 3 has no name"), std::string::npos) << e.message();
  }
}

TEST(CalibrationJson, RejectsForeignOrBrokenFiles) {
  EXPECT_THROW(CalibrationSetFromJson("{", "c.json"), InputError);
  EXPECT_THROW(CalibrationSetFromJson(R"({"format":"other"})", "c.json"), InputError);
  EXPECT_THROW(CalibrationSetFromJson(R"({"format":"trueaxis-calibration","version":2,"sensors":{}})", "c.json"), InputError);
  EXPECT_THROW(CalibrationSetFromJson(R"({"format":"trueaxis-calibration","version":1,"sensors":{"a":{"gain":"x","offset_c":0}}})", "c.json"),
               InputError);
  EXPECT_THROW(CalibrationSetFromJson(R"({"format":"trueaxis-calibration","version":1,"sensors":{"a":{"gain":-1,"offset_c":0}}})", "c.json"),
               InputError);
}

class CalibrateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("trueaxis_cal_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(CalibrateCli, WritesCalibrationFile) {
  const auto s = MakeSession({{1.02, -0.3}});
  std::string csv = "time_s,ref,x_nut\n";
  for (std::size_t i = 0; i < s.reference.size(); ++i)
    csv += std::to_string(i) + "," + std::to_string(s.reference[i]) + "," + std::to_string(s.sensors[0][i]) + "\n";
  WriteTextFile((dir_ / "session.csv").string(), csv);
  const auto r = testing::RunCli("calibrate --session " + (dir_ / "session.csv").string() + " --reference ref --out " +
                                 (dir_ / "cal.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("x_nut"), std::string::npos);
  const auto set = ReadCalibrationFile((dir_ / "cal.json").string());
  EXPECT_NEAR(set.sensors.at("x_nut").calibration.gain, 1.02, 0.002);
  EXPECT_NEAR(set.sensors.at("x_nut").calibration.offset_c, -0.3, 0.05);
}

TEST_F(CalibrateCli, BadInputsExitTwoWithClearMessage) {
  WriteTextFile((dir_ / "bad.csv").string(), "ref,a\n20,20\n25,x\n");
  auto r = testing::RunCli("calibrate --session " + (dir_ / "bad.csv").string() + " --reference ref --out " +
                           (dir_ / "cal.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.csv:3"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "cal.json"));
  WriteTextFile((dir_ / "ok.csv").string(), "ref,a\n20,20\n30,30\n40,40\n");
  r = testing::RunCli("calibrate --session " + (dir_ / "ok.csv").string() + " --reference nope --out " +
                      (dir_ / "cal.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("reference"), std::string::npos) << r.output;
  r = testing::RunCli("calibrate --session " + (dir_ / "missing.csv").string() + " --reference ref --out " +
                      (dir_ / "cal.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.csv"), std::string::npos) << r.output;
}

TEST_F(CalibrateCli, RefusesAnOutputThatIsTheSession) {
  const std::string session = (dir_ / "s.csv").string();
  WriteTextFile(session, "ref,a\n20,20\n30,30\n40,40\n");
  const auto r = testing::RunCli("calibrate --session " + session + " --reference ref --out " + session);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--out'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("s.csv"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(session), "ref,a\n20,20\n30,30\n40,40\n");
}

}  // namespace
}  // namespace trueaxis::signal
