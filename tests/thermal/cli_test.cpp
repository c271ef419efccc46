// `trueaxis thermal` end to end through the built CLI (TRUEAXIS_CLI_PATH).
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::thermal {
namespace {

using testing::RunCli;

// The synthetic spindle-block series of test_util.hpp, written as CSV.
std::string WriteFixture(const std::string& dir) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(2);
  const std::string path = dir + "/series.csv";
  WriteThermalSeriesCsv(s, path);
  return path;
}

TEST(ThermalCli, FitPredictEvaluateWithReport) {
  const std::string dir = testing::TempDir("cli_ok");
  const std::string series = WriteFixture(dir);
  auto fit = RunCli("thermal fit --series " + series + " --model ridge --sensors 2 -o " + dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_NE(fit.output.find("T[s0]"), std::string::npos) << fit.output;  // the heated sensor is chosen
  auto pred = RunCli("thermal predict --model " + dir + "/m.json --series " + series + " -o " + dir + "/p.csv");
  ASSERT_EQ(pred.exit_code, 0) << pred.output;
  const std::string text = ReadTextFile(dir + "/p.csv");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 8 * 240 + 1);
  // The series holds the measured error too: it is written beside the prediction, with the residual.
  EXPECT_EQ(text.substr(0, text.find('\n')), "time_s,e_e_predicted_um,e_e_measured_um,e_e_residual_um");
  EXPECT_NE(pred.output.find("residual RMSE"), std::string::npos) << pred.output;

  auto ev = RunCli("thermal evaluate --series " + series +
                   " --train-blocks 0-1 --validate-blocks 2-3 --particles 20 --pso-iterations 10 --epochs 20"
                   " --temperature-inputs 2 --report " + dir + "/r.html --markdown " + dir + "/r.md");
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  for (const char* model : {"no compensation", "mlr", "ridge", "pso-bp", "hysteresis"})
    EXPECT_NE(ev.output.find(model), std::string::npos) << model;
  EXPECT_NE(ev.output.find("validate: 960 rows in blocks 2(0 rpm"), std::string::npos) << ev.output;
  const std::string html = ReadTextFile(dir + "/r.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("measured"), std::string::npos);
  EXPECT_NE(html.find("Chosen temperature sensors"), std::string::npos);
  const std::string md = ReadTextFile(dir + "/r.md");
  EXPECT_NE(md.find("| ridge | e |"), std::string::npos) << md;
}

void ExpectBadInput(const std::string& args, const std::vector<std::string>& must_contain) {
  auto r = RunCli(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  for (const auto& s : must_contain) EXPECT_NE(r.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.output;
}

void Write(const std::string& path, const std::string& text) { WriteTextFile(path, text); }

TEST(ThermalCli, BadInputsExitTwoNamingFileLineAndField) {
  const std::string dir = testing::TempDir("cli_bad");
  const std::string bad = dir + "/bad.csv";
  Write(bad, "time_s,t_a_c,t_b_c,e_x_um\n0,20,21,1\n15,20.1,21,1.1\n30,warm,21,1.2\n");
  ExpectBadInput("thermal fit --series " + bad + " -o " + dir + "/m.json", {"bad.csv:4", "t_a_c", "warm"});
  ExpectBadInput("thermal evaluate --series " + dir + "/nope.csv", {"nope.csv", "cannot open"});
  Write(dir + "/noerr.csv", "time_s,t_a_c\n0,20\n15,20.5\n30,21\n");
  ExpectBadInput("thermal fit --series " + dir + "/noerr.csv -o " + dir + "/m.json", {"noerr.csv", "no error column"});

  std::string gap = "time_s,t_a_c,t_b_c,e_x_um\n";
  for (int r = 0; r < 40; ++r)
    gap += std::to_string(r * 15) + "," + std::to_string(20 + r * 0.01) + "," + std::to_string(21 - r * 0.02) + "," +
           (r >= 10 && r < 20 ? std::string("") : std::to_string(r * 0.1)) + "\n";
  Write(dir + "/gap.csv", gap);
  ExpectBadInput("thermal fit --series " + dir + "/gap.csv -o " + dir + "/m.json", {"gap.csv:12", "'x'", "gap of 10 rows"});

  // A sensor that dies half way: dropped with a warning (exit 0) or, with --strict, refused.
  std::string dies = "time_s,t_a_c,t_b_c,e_x_um\n";
  for (int r = 0; r < 40; ++r)
    dies += std::to_string(r * 15) + "," + std::to_string(20 + r * 0.01) + "," +
            (r >= 20 ? std::string("nan") : std::to_string(21 - r * 0.02)) + "," + std::to_string(r * 0.1) + "\n";
  Write(dir + "/dies.csv", dies);
  auto ok = RunCli("thermal fit --series " + dir + "/dies.csv --model mlr -o " + dir + "/d.json");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("warning: temperature 'b' dropped"), std::string::npos) << ok.output;
  ExpectBadInput("thermal fit --strict --series " + dir + "/dies.csv -o " + dir + "/d2.json", {"dies.csv:22", "'b'", "died"});

  // Options and models.
  const std::string good = WriteFixture(dir);
  ExpectBadInput("thermal evaluate --series " + good + " --train-blocks 0-9", {"--train-blocks", "blocks 0..3"});
  // Validating on every row leaves nothing to train on: the option that did it is named.
  ExpectBadInput("thermal evaluate --series " + good + " --validate-rows 0-1919",
                 {"field '--validate-rows'", "fewer than 3 training rows (0 of 1920"});
  ExpectBadInput("thermal fit --series " + good + " --model magic -o " + dir + "/x.json", {"--model", "magic"});
  ExpectBadInput("thermal fit --series " + good + " --select psychic -o " + dir + "/x.json", {"--select"});
  ExpectBadInput("thermal fit --series " + good + " --channels nope -o " + dir + "/x.json", {"'nope'", "no such error channel"});
  // The fitted model needs sensor s0; a series without it is refused by name.
  ASSERT_EQ(RunCli("thermal fit --series " + good + " --sensors 1 -o " + dir + "/m1.json").exit_code, 0);
  Write(dir + "/other.csv", "time_s,t_q_c\n0,20\n15,20.5\n30,21\n");
  ExpectBadInput("thermal predict --model " + dir + "/m1.json --series " + dir + "/other.csv", {"'s0'", "needs temperature"});
  Write(dir + "/broken.json", "{\"model\": {\"kind\": \"linear\", \"ridge_lambda\": -1,");
  ExpectBadInput("thermal predict --model " + dir + "/broken.json --series " + good, {"broken.json", "not valid JSON"});
  Write(dir + "/neg.json", R"({"model": {"kind": "linear", "ridge_lambda": -1, "sensors": [], "channels": []}})");
  ExpectBadInput("thermal predict --model " + dir + "/neg.json --series " + good, {"neg.json", "ridge_lambda"});
  // A damaged coefficient: predictions no machine's error reaches are refused, not written.
  const std::string m1 = ReadTextFile(dir + "/m1.json");
  const auto at = m1.find("\"intercept_um\": ");
  ASSERT_NE(at, std::string::npos) << m1;
  Write(dir + "/huge.json", m1.substr(0, at) + "\"intercept_um\": 1e308, \"old\": " + m1.substr(at + 16));
  ExpectBadInput("thermal predict --model " + dir + "/huge.json --series " + good + " -o " + dir + "/ph.csv",
                 {"huge.json", "field 'channels'", "damaged"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/ph.csv"));
}

}  // namespace
}  // namespace trueaxis::thermal

namespace trueaxis::thermal {
namespace {

// More sensors than the recording has, and a recording too short to determine a fit: both are said.
TEST(ThermalCliWarnings, TooManySensorsAndTooFewRowsAreSaid) {
  const std::string dir = testing::TempDir("cli_warn");
  const std::string series = WriteFixture(dir);
  auto many = RunCli("thermal fit --series " + series + " --model ridge --sensors 50 -o " + dir + "/m.json");
  EXPECT_EQ(many.exit_code, 0) << many.output;
  EXPECT_NE(many.output.find("warning: --sensors 50"), std::string::npos) << many.output;
  // An 8 h recording cannot identify the 4.5 h lag of the default grid: said, not silently dropped.
  EXPECT_NE(many.output.find("16200 s not offered"), std::string::npos) << many.output;
  std::ofstream(dir + "/three.csv") << "time_s,t_a_c,t_b_c,e_x_um\n0,20,21,1\n15,20.5,21,1.5\n30,21,21.2,2\n";
  auto few = RunCli("thermal fit --series " + dir + "/three.csv --model mlr --sensors 1 -o " + dir + "/m3.json");
  EXPECT_NE(few.output.find("barely determined"), std::string::npos) << few.output;
}

// A recording without a spindle column is one speed block: the default split is in time (the
// last 30 % validated), never silently in-sample; --validate-last sets the fraction.
TEST(ThermalCliSplit, ARecordingWithoutSpeedIsSplitInTimeNotInSample) {
  const std::string dir = testing::TempDir("cli_split");
  std::ofstream csv(dir + "/nospeed.csv");
  csv << "time_s,t_a_c,t_b_c,e_x_um\n";
  for (int i = 0; i < 200; ++i) {
    const double a = 20 + 5 * (1 - std::exp(-i * 60.0 / 9000)), b = 21 + 0.3 * std::sin(i * 60.0 / 5000);
    csv << i * 60 << "," << a << "," << b << "," << 3 * (a - 20) << "\n";
  }
  csv.close();
  auto ev = RunCli("thermal evaluate --series " + dir + "/nospeed.csv --models mlr");
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  EXPECT_NE(ev.output.find("split in time: train on the first 140 rows"), std::string::npos) << ev.output;
  EXPECT_EQ(ev.output.find("in-sample"), std::string::npos) << ev.output;
  auto tenth = RunCli("thermal evaluate --series " + dir + "/nospeed.csv --models mlr --validate-last 0.1");
  EXPECT_NE(tenth.output.find("validate on the last 10 %: 20 rows"), std::string::npos) << tenth.output;
  auto both = RunCli("thermal evaluate --series " + dir + "/nospeed.csv --models mlr --validate-last 0.1 --train-blocks 0");
  EXPECT_EQ(both.exit_code, 2) << both.output;
}


// Several files are experiments: evaluated leave-one-experiment-out by default; an explicit
// sensor list is used as given; a split by rows; conflicting splits refused.
TEST(ThermalCliExperiments, SeveralFilesSensorListAndRowSplit) {
  const std::string dir = testing::TempDir("cli_exp");
  std::string files;
  for (unsigned e = 0; e < 3; ++e) {
    ThermalSeries s = testing::MakeSpindleBlockSeries(10 + e);
    s.source = dir + "/run" + std::to_string(e) + ".csv";
    WriteThermalSeriesCsv(s, s.source);
    files += " " + s.source;
  }
  auto loeo = RunCli("thermal evaluate --series" + files + " --models mlr,hysteresis");
  ASSERT_EQ(loeo.exit_code, 0) << loeo.output;
  EXPECT_NE(loeo.output.find("leave one experiment out: 3 folds"), std::string::npos) << loeo.output;
  EXPECT_NE(loeo.output.find("ridge (all sensors)"), std::string::npos) << loeo.output;
  auto one = RunCli("thermal evaluate --series" + files + " --models mlr --validate-experiments 2");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_NE(one.output.find("validate on " + dir + "/run2.csv"), std::string::npos) << one.output;

  auto listed = RunCli("thermal fit --series" + files + " --model mlr --sensors-list s2,s1 -o " + dir + "/m.json");
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  const std::string model = ReadTextFile(dir + "/m.json");
  EXPECT_NE(model.find("\"s2\""), std::string::npos);
  EXPECT_EQ(model.find("\"s0\""), std::string::npos) << "a sensor that was not listed was used";
  auto unknown = RunCli("thermal fit --series" + files + " --sensors-list s1,nope -o " + dir + "/m2.json");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("nope"), std::string::npos) << unknown.output;

  const std::string first = dir + "/run0.csv";
  auto rows = RunCli("thermal evaluate --series " + first + " --models mlr --validate-rows 1500-1919");
  ASSERT_EQ(rows.exit_code, 0) << rows.output;
  EXPECT_NE(rows.output.find("validate on rows 1500-1919 (420 rows)"), std::string::npos) << rows.output;
  auto two = RunCli("thermal evaluate --series " + first + " --models mlr --validate-rows 1-5 --validate-hours 1-2");
  EXPECT_EQ(two.exit_code, 2) << two.output;
}

}  // namespace
}  // namespace trueaxis::thermal
