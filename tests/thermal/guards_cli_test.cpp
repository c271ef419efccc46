// `trueaxis thermal` on recordings as users have them: units that are not what the columns say,
// columns with other names or no header, missing values, files cut out of a longer recording,
// splits in time. Each case used to give an answer without a word; now it is refused or said.
#include <cmath>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "test_util.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::thermal {
namespace {

using testing::RunCli;

bool Has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The command is refused (exit 2) with every one of `parts` in its message.
void ExpectRefused(const std::string& args, const std::vector<std::string>& parts) {
  const auto r = RunCli(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  for (const auto& part : parts) EXPECT_TRUE(Has(r.output, part)) << "missing '" << part << "' in:\n" << r.output;
}

// A 6 h warm-up and cool-down at one row a minute: sensor a heats 20 → 28 °C and cools, b is the
// room; the error is 2 µm/°C on a (+0.5 µm/°C on b). `row` formats one row from (t_s, a, b, e).
std::string Recording(const std::string& header, const std::function<std::string(double, double, double, double)>& row,
                      int rows = 360) {
  std::string csv = header + "\n";
  for (int r = 0; r < rows; ++r) {
    const double t = r * 60.0, h = t / 3600;
    const double a = h < 3 ? 20 + 8 * (1 - std::exp(-h / 0.8)) : 20 + 8 * (1 - std::exp(-3 / 0.8)) * std::exp(-(h - 3) / 0.8);
    const double b = 21 + 0.4 * std::sin(h);
    csv += row(t, a, b, 2 * (a - 20) + 0.5 * (b - 21)) + "\n";
  }
  return csv;
}

std::string Celsius(double t, double a, double b, double e) { return fmt::format("{},{:.10f},{:.10f},{:.10f}", t, a, b, e); }

// The first line of the fit output that starts with `prefix` (the model's equation or its RMSE).
std::string LineOf(const std::string& output, const std::string& prefix) {
  const auto at = output.find("\n" + prefix);
  if (at == std::string::npos) return "";
  return output.substr(at + 1, output.find('\n', at + 1) - at - 1);
}

TEST(ThermalGuards, FahrenheitIsRefusedAndConvertedWhenSaid) {
  const std::string dir = testing::TempDir("guard_f");
  WriteTextFile(dir + "/c.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", Celsius));
  WriteTextFile(dir + "/f.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", [](double t, double a, double b, double e) {
                  return Celsius(t, a * 9 / 5 + 32, b * 9 / 5 + 32, e);
                }));
  const std::string fit = " --model mlr --sensors-list a,b --lags-s none -o ";
  // Named: the file, the header line, the coolest sensor's column (the room) and the option.
  ExpectRefused("thermal fit --series " + dir + "/f.csv" + fit + dir + "/f.json",
                {"f.csv:1", "t_b_c", "--temperature-unit F"});
  // Said in °F: the same model as from the °C file (coefficients in µm/°C).
  auto f = RunCli("thermal fit --series " + dir + "/f.csv --temperature-unit F" + fit + dir + "/f.json");
  auto c = RunCli("thermal fit --series " + dir + "/c.csv" + fit + dir + "/c.json");
  ASSERT_EQ(f.exit_code, 0) << f.output;
  ASSERT_EQ(c.exit_code, 0) << c.output;
  // The coefficients (6 significant digits) after the intercept.
  auto coefficients = [](const std::string& line) { return line.substr(line.find(" +", line.find("= "))); };
  ASSERT_TRUE(Has(LineOf(c.output, "x: e_um"), "*T[a]")) << c.output;
  EXPECT_EQ(coefficients(LineOf(f.output, "x: e_um")), coefficients(LineOf(c.output, "x: e_um"))) << f.output << c.output;
  // Predicting °F data with a °C model is refused the same way.
  ExpectRefused("thermal predict --model " + dir + "/c.json --series " + dir + "/f.csv", {"--temperature-unit F"});
}

TEST(ThermalGuards, KelvinIsRefusedAndConvertedWhenSaid) {
  const std::string dir = testing::TempDir("guard_k");
  WriteTextFile(dir + "/k.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", [](double t, double a, double b, double e) {
                  return Celsius(t, a + 273.15, b + 273.15, e);
                }));
  ExpectRefused("thermal fit --series " + dir + "/k.csv --model mlr -o " + dir + "/k.json", {"k.csv:1", "--temperature-unit K"});
  auto k = RunCli("thermal fit --series " + dir + "/k.csv --temperature-unit K --model mlr -o " + dir + "/k.json");
  EXPECT_EQ(k.exit_code, 0) << k.output;
  ThermalReadOptions ro;
  ro.temperature_unit = TemperatureUnit::kKelvin;
  const ThermalSeries s = ReadThermalSeriesCsv(dir + "/k.csv", ro);
  EXPECT_NEAR(s.temperatures_c(0, 0), 20.0, 1e-9);
}

// An error column in mm labelled µm gave "fit RMSE 0.000 um": refused, and converted when said.
TEST(ThermalGuards, AnErrorColumnInMillimetresIsRefusedAndConvertedWhenSaid) {
  const std::string dir = testing::TempDir("guard_mm");
  WriteTextFile(dir + "/mm.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", [](double t, double a, double b, double e) {
                  return fmt::format("{},{:.4f},{:.4f},{:.8f}", t, a, b, e / 1000);
                }));
  ExpectRefused("thermal fit --series " + dir + "/mm.csv --model mlr -o " + dir + "/m.json", {"e_x_um", "--error-unit mm"});
  auto mm = RunCli("thermal fit --series " + dir + "/mm.csv --error-unit mm --model mlr --sensors-list a,b --lags-s none -o " +
                   dir + "/m.json");
  ASSERT_EQ(mm.exit_code, 0) << mm.output;
  EXPECT_TRUE(Has(mm.output, "*T[a]")) << mm.output;
  EXPECT_TRUE(Has(mm.output, "+2*T[a]") || Has(mm.output, "+1.99999") || Has(mm.output, "+2.00000")) << mm.output;
  // Said to be µm: taken as it is (a tiny drift is the user's to judge).
  auto um = RunCli("thermal fit --series " + dir + "/mm.csv --error-unit um --model mlr -o " + dir + "/u.json");
  EXPECT_EQ(um.exit_code, 0) << um.output;
}

// The docs say the values filled in are reported: per column, how many, from which line.
TEST(ThermalGuards, MissingValuesFilledAreReportedPerColumn) {
  const std::string dir = testing::TempDir("guard_nan");
  int row = 0;
  WriteTextFile(dir + "/nan.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", [&](double t, double a, double b, double e) {
                  ++row;
                  if (row == 50 || row == 51) return fmt::format("{},{:.4f},{:.4f},nan", t, a, b);
                  if (row == 90) return fmt::format("{},,{:.4f},{:.5f}", t, b, e);
                  return Celsius(t, a, b, e);
                }));
  auto fit = RunCli("thermal fit --series " + dir + "/nan.csv --model mlr -o " + dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_TRUE(Has(fit.output, "error channel 'x': 2 missing value(s) filled by linear interpolation in time (the first "
                              "at line 51)")) << fit.output;
  EXPECT_TRUE(Has(fit.output, "temperature 'a': 1 missing value(s) filled")) << fit.output;
}

// predict on a file that starts hours into the recording: the lags start there as if at rest.
TEST(ThermalGuards, PredictSaysWhichRowsLackTheLagHistory) {
  const std::string dir = testing::TempDir("guard_lag");
  const ThermalSeries s = testing::MakeSpindleBlockSeries(3);
  WriteThermalSeriesCsv(s, dir + "/all.csv");
  std::vector<Eigen::Index> later;
  for (Eigen::Index r = 1000; r < s.Rows(); ++r) later.push_back(r);
  WriteThermalSeriesCsv(SelectRows(s, later), dir + "/later.csv");
  auto fit = RunCli("thermal fit --series " + dir + "/all.csv --model ridge --lags-s 1800 --sensors-list s0@lag1800s -o " +
                    dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  auto p = RunCli("thermal predict --model " + dir + "/m.json --series " + dir + "/later.csv -o " + dir + "/p.csv");
  ASSERT_EQ(p.exit_code, 0) << p.output;
  // 15 s rows: 3 × 1800 s = 5400 s = the first 360 rows.
  EXPECT_TRUE(Has(p.output, "the first 360 row(s) (5400 s = 3 × τ) lack the lag history")) << p.output;
  // A model without lags has nothing to say.
  ASSERT_EQ(RunCli("thermal fit --series " + dir + "/all.csv --model ridge --lags-s none -o " + dir + "/n.json").exit_code, 0);
  auto plain = RunCli("thermal predict --model " + dir + "/n.json --series " + dir + "/later.csv -o " + dir + "/q.csv");
  EXPECT_FALSE(Has(plain.output, "lag history")) << plain.output;
}

// --validate-rows A-B trains only on the rows before A unless asked: the rows after hold the future.
TEST(ThermalGuards, ValidatingRowsNeverTrainsOnTheRowsAfterUnlessAsked) {
  const std::string dir = testing::TempDir("guard_rows");
  WriteThermalSeriesCsv(testing::MakeSpindleBlockSeries(4), dir + "/s.csv");
  auto ev = RunCli("thermal evaluate --series " + dir + "/s.csv --models mlr --lags-s none --validate-rows 1000-1400");
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  EXPECT_TRUE(Has(ev.output, "validate on rows 1000-1400 (401 rows), train on the 1000 rows before them (not on the 519 "
                             "rows after")) << ev.output;
  auto leak = RunCli("thermal evaluate --series " + dir + "/s.csv --models mlr --lags-s none --validate-rows 1000-1400 "
                     "--train-after-validation");
  ASSERT_EQ(leak.exit_code, 0) << leak.output;
  EXPECT_TRUE(Has(leak.output, "train on the other 1519 rows, including those after them")) << leak.output;
  ExpectRefused("thermal evaluate --series " + dir + "/s.csv --models mlr --validate-rows 0-100", {"--train-after-validation"});
}

// Three 8 h experiments support the lags an 8 h run does: 16 200 s is more than a third of one.
TEST(ThermalGuards, LagsAreJudgedByTheLongestExperimentNotTheSum) {
  const std::string dir = testing::TempDir("guard_exp");
  std::string files;
  for (unsigned e = 0; e < 3; ++e) {
    const std::string path = dir + "/run" + std::to_string(e) + ".csv";
    WriteThermalSeriesCsv(testing::MakeSpindleBlockSeries(20 + e), path);
    files += " " + path;
  }
  auto fit = RunCli("thermal fit --series" + files + " --model ridge --sensors 2 -o " + dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_TRUE(Has(fit.output, "16200 s not offered: longer than a third of the longest experiment (8.00 h)")) << fit.output;
  EXPECT_FALSE(Has(ReadTextFile(dir + "/m.json"), "@lag16200s"));
}

// Time in minutes read as seconds: said, and the hysteresis fit blames the start-up, not the trend.
TEST(ThermalGuards, TimeInMinutesIsSaidAndReadWhenNamed) {
  const std::string dir = testing::TempDir("guard_min");
  auto minutes = [](double t, double a, double b, double e) { return Celsius(t / 60, a, b, e); };
  WriteTextFile(dir + "/as_s.csv", Recording("time_s,t_a_c,t_b_c,e_x_um", minutes));
  auto wrong = RunCli("thermal fit --series " + dir + "/as_s.csv --model hysteresis --lags-s none -o " + dir + "/h.json");
  ASSERT_EQ(wrong.exit_code, 0) << wrong.output;
  EXPECT_TRUE(Has(wrong.output, "column 'time_s' is read as seconds")) << wrong.output;
  EXPECT_TRUE(Has(wrong.output, "--time-unit min")) << wrong.output;
  EXPECT_TRUE(Has(wrong.output, "360 of 360 training rows are start-up")) << wrong.output;
  EXPECT_FALSE(Has(wrong.output, "never passes")) << wrong.output;
  // Said: --time-unit min, or a column named time_min. Then the warm-up is heating.
  for (const std::string& way : {std::string(" --time-unit min"), std::string()}) {
    const std::string path = dir + (way.empty() ? "/named.csv" : "/as_s.csv");
    if (way.empty()) WriteTextFile(path, Recording("time_min,t_a_c,t_b_c,e_x_um", minutes));
    auto ok = RunCli("thermal fit --series " + path + way + " --model hysteresis --lags-s none -o " + dir + "/h2.json");
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_FALSE(Has(ok.output, "read as seconds")) << ok.output;
    EXPECT_FALSE(Has(ok.output, "are start-up")) << ok.output;
    EXPECT_FALSE(Has(ok.output, "rows are heating")) << ok.output;  // heating has rows of its own
  }
}

TEST(ThermalGuards, ColumnsMappedByNameWithoutHeaderOrTime) {
  const std::string dir = testing::TempDir("guard_cols");
  WriteTextFile(dir + "/dl.csv", Recording("time_s,t_a_c,t_b_c,delta L", Celsius));
  ExpectRefused("thermal fit --series " + dir + "/dl.csv --model mlr -o " + dir + "/m.json", {"unknown column", "--error-column"});
  auto mapped = RunCli("thermal fit --series " + dir + "/dl.csv --error-column 'delta L' --model mlr --lags-s none -o " +
                       dir + "/m.json");
  ASSERT_EQ(mapped.exit_code, 0) << mapped.output;
  EXPECT_TRUE(Has(mapped.output, "delta_L: fit RMSE")) << mapped.output;

  // No header row: said so, and read with generated names.
  const std::string text = ReadTextFile(dir + "/dl.csv");
  WriteTextFile(dir + "/nohead.csv", text.substr(text.find('\n') + 1));
  ExpectRefused("thermal fit --series " + dir + "/nohead.csv --model mlr -o " + dir + "/m.json",
                {"the header seems missing", "--no-header"});
  auto nohead = RunCli("thermal fit --series " + dir + "/nohead.csv --no-header --time-column col1 --error-column col4 "
                       "--model mlr --lags-s none -o " + dir + "/n.json");
  ASSERT_EQ(nohead.exit_code, 0) << nohead.output;
  EXPECT_TRUE(Has(nohead.output, "col4: fit RMSE")) << nohead.output;
  EXPECT_TRUE(Has(nohead.output, "T[col2]")) << nohead.output;
  EXPECT_EQ(LineOf(nohead.output, "col4: fit RMSE"), LineOf(mapped.output, "delta_L: fit RMSE").replace(0, 7, "col4"));

  // No time column: the sample interval is stated, and time-based models work as with the column.
  std::string notime;
  for (std::size_t at = 0; at < text.size();) {
    const auto end = text.find('\n', at);
    const std::string line = text.substr(at, end - at);
    notime += line.substr(line.find(',') + 1) + "\n";
    at = end + 1;
  }
  WriteTextFile(dir + "/notime.csv", notime);
  ExpectRefused("thermal fit --series " + dir + "/notime.csv --error-column 'delta L' --model hysteresis -o " + dir + "/h.json",
                {"needs time_s"});
  auto stated = RunCli("thermal fit --series " + dir + "/notime.csv --error-column 'delta L' --sample-interval-s 60 "
                       "--model hysteresis --lags-s none -o " + dir + "/h.json");
  auto timed = RunCli("thermal fit --series " + dir + "/dl.csv --error-column 'delta L' --model hysteresis --lags-s none -o " +
                      dir + "/h2.json");
  ASSERT_EQ(stated.exit_code, 0) << stated.output;
  ASSERT_EQ(timed.exit_code, 0) << timed.output;
  EXPECT_EQ(LineOf(stated.output, "delta_L: fit RMSE"), LineOf(timed.output, "delta_L: fit RMSE"));
  ExpectRefused("thermal fit --series " + dir + "/dl.csv --error-column 'delta L' --sample-interval-s 60 -o " + dir + "/x.json",
                {"leave out --sample-interval-s"});
}

TEST(ThermalGuards, ReportsTheCountCvTheListedSensorsAndTheInputs) {
  const std::string dir = testing::TempDir("guard_report");
  WriteThermalSeriesCsv(testing::MakeSpindleBlockSeries(5), dir + "/s.csv");
  auto fit = RunCli("thermal fit --series " + dir + "/s.csv --model ridge -o " + dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_TRUE(Has(fit.output, "chosen by time-ordered cross-validation; held-out RMS µm (geometric mean over the folds): constant: ")) << fit.output;
  EXPECT_TRUE(Has(fit.output, "; sensors 1: ")) << fit.output;
  EXPECT_TRUE(Has(fit.output, ", all: ")) << fit.output;
  auto listed = RunCli("thermal evaluate --series " + dir + "/s.csv --models ridge --sensors-list s0,s1 --lags-s none");
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_TRUE(Has(listed.output, "ridge (listed sensors)")) << listed.output;
  EXPECT_FALSE(Has(listed.output, "(all sensors)")) << listed.output;
  auto lags = RunCli("thermal evaluate --series " + dir + "/s.csv --models ridge --lags-s 600,1800");
  ASSERT_EQ(lags.exit_code, 0) << lags.output;
  EXPECT_TRUE(Has(lags.output, "1920 rows, 3 sensors (9 inputs with lags), 1 channels")) << lags.output;
}

}  // namespace
}  // namespace trueaxis::thermal
