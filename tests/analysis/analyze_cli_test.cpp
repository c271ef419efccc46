// `trueaxis analyze` end to end: real files, JSON contract, report, and every
// bad input of issue 2 (exit code 2, message naming file, line and field).
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/shared_data.hpp"
#include <nlohmann/json.hpp>

#include "test_util.hpp"

using trueaxis::testing::RunCli;
using trueaxis::testing::WriteTemp;

namespace {

const std::string kShared = TRUEAXIS_SHARED_DATA_DIR;
const std::string kFatSat = kShared + "/ecmc/fat_sat_test.dat";
const std::string kMcu = kShared + "/ecmc/mcu1025_fat_sat.dat";
const std::string kExample = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_cold.csv";

const char* kGoodHeader = "run,direction,target_mm,deviation_um\n";

std::string Q(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST(AnalyzeCli, JsonHasEveryContractKey) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kFatSat);
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kMcu);
  for (const auto& file : {kFatSat, kMcu, kExample}) {
    const auto r = RunCli("analyze " + Q(file) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"A_um", "A_up_um", "A_down_um", "B_um", "B_mean_um", "E_um", "E_up_um", "E_down_um",
                            "M_um", "R_um", "R_up_um", "R_down_um", "P_um", "Pa_um", "Ps_max_um", "Ps_mean_um",
                            "U_max_um", "U_mean_um"}) {
      ASSERT_TRUE(j.contains(key)) << key;
      EXPECT_TRUE(j[key].is_number()) << key;
      EXPECT_GE(j[key].get<double>(), key == std::string("B_mean_um") ? -1e9 : 0.0) << key;
    }
    EXPECT_EQ(j["standard"], "ISO 230-2:2014");
    EXPECT_EQ(j["per_target"].size(), j["positions"].get<std::size_t>());
    EXPECT_GE(j["runs"].get<int>(), 2);
    EXPECT_FALSE(j.contains("decomposition"));
  }
}

TEST(AnalyzeCli, EcmcNumbersMatchTheLibrary) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kMcu);
  const auto j = nlohmann::json::parse(RunCli("analyze " + Q(kMcu) + " --json").out);
  EXPECT_EQ(j["positions"], 5);
  EXPECT_EQ(j["runs"], 5);
  EXPECT_NEAR(j["A_um"].get<double>(), 204.76, 0.02);
  EXPECT_NEAR(j["M_um"].get<double>(), 48.09, 0.02);
}

TEST(AnalyzeCli, StandardsChangeTheCoverageFactor) {
  const auto j14 = nlohmann::json::parse(RunCli("analyze " + Q(kExample) + " --json").out);
  const auto j88 = nlohmann::json::parse(RunCli("analyze " + Q(kExample) + " --json --standard 'ISO 230-2:1988'").out);
  EXPECT_EQ(j88["standard"], "ISO 230-2:1988");
  EXPECT_NEAR(j88["R_up_um"].get<double>(), 1.5 * j14["R_up_um"].get<double>(), 1e-9);
  const auto jis = nlohmann::json::parse(RunCli("analyze " + Q(kExample) + " --json --standard 'JIS B 6192'").out);
  EXPECT_EQ(jis["standard"], "ISO 230-2:1997");
  EXPECT_EQ(jis["standard_requested"], "JIS B 6192");
  const auto bad = RunCli("analyze " + Q(kExample) + " --standard 'ISO 9999'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("standard"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("ISO 230-2:2014"), std::string::npos) << bad.err;
}

TEST(AnalyzeCli, TextTableDecompositionCompareAndReport) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kFatSat);
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kMcu);
  const auto html = (std::filesystem::temp_directory_path() / "trueaxis_analyze_cli_test.html").string();
  std::filesystem::remove(html);
  // Compared with itself: the same test, so the comparison is allowed and every change is 0.
  const auto r = RunCli("analyze " + Q(kFatSat) + " --lead-mm 5 --compare " + Q(kFatSat) + " --report " + Q(html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("bidirectional accuracy"), std::string::npos);
  EXPECT_NE(r.out.find("aliased"), std::string::npos);  // 5.12 mm targets vs 5 mm lead
  EXPECT_NE(r.out.find("Comparison with"), std::string::npos);
  ASSERT_TRUE(std::filesystem::exists(html));
  const auto page = trueaxis::testing::Slurp(html);
  EXPECT_NE(page.find("<svg"), std::string::npos);
  EXPECT_NE(page.find("After: forward and reverse mean deviation"), std::string::npos);
  EXPECT_NE(page.find("decomposition"), std::string::npos);
  EXPECT_EQ(page.find("<script"), std::string::npos);
  std::filesystem::remove(html);

  const auto j = nlohmann::json::parse(
      RunCli("analyze " + Q(kFatSat) + " --json --lead-mm 5 --compare " + Q(kFatSat)).out);
  ASSERT_TRUE(j.contains("decomposition"));
  EXPECT_FALSE(j["decomposition"]["periodic_fitted"].get<bool>());
  ASSERT_TRUE(j.contains("compare"));
  EXPECT_NEAR(j["compare"]["change_um"]["A_um"].get<double>(),
              j["compare"]["after"]["A_um"].get<double>() - j["A_um"].get<double>(), 1e-9);
  EXPECT_NEAR(j["compare"]["change_um"]["A_um"].get<double>(), 0, 1e-12);
  // Two different stages' tests (−10…10 mm against 15…56 mm) are not a before/after.
  const auto unrelated = RunCli("analyze " + Q(kFatSat) + " --compare " + Q(kMcu));
  EXPECT_EQ(unrelated.exit_code, 2);
  EXPECT_NE(unrelated.err.find("not a before/after of the same test"), std::string::npos) << unrelated.err;
}

// Deviations in mm under a deviation_um header read as a perfect axis: analyze says so (stderr),
// and still evaluates; the same run in µm gets no such warning.
TEST(AnalyzeCli, DeviationsThatLookLikeMillimetresAreWarnedAbout) {
  const auto run_with = [&](double scale) {
    std::string csv = "# axis: X\n" + std::string(kGoodHeader);
    for (int run = 1; run <= 2; ++run)
      for (int t = 0; t <= 400; t += 50)
        for (const char* dir : {"+", "-"})
          csv += fmt::format("{},{},{},{}\n", run, dir, t, scale * (0.02 * t + run));  // up to 10 µm
    return RunCli("analyze " + Q(WriteTemp(scale < 1 ? "in_mm.csv" : "in_um.csv", csv)));
  };
  const auto um = run_with(1), mm = run_with(0.001);
  EXPECT_EQ(um.exit_code, 0) << um.err;
  EXPECT_EQ(um.err.find("warning"), std::string::npos) << um.err;
  EXPECT_EQ(mm.exit_code, 0) << mm.err;
  EXPECT_NE(mm.err.find("in_mm.csv: every deviation is under 0.2 µm (largest 0.01 µm) over 400 mm"), std::string::npos)
      << mm.err;
}

TEST(AnalyzeCli, LeadFromMetadataAndBadLead) {
  std::string csv = "# axis: X\n# lead_mm: 10\n" + std::string(kGoodHeader);
  for (int run = 1; run <= 3; ++run)
    for (int t = 0; t <= 40; t += 4)
      csv += std::to_string(run) + ",+," + std::to_string(t) + "," + std::to_string(0.1 * t + 0.01 * run) + "\n" +
             std::to_string(run) + ",-," + std::to_string(t) + "," + std::to_string(0.1 * t + 1 - 0.01 * run) + "\n";
  const auto f = WriteTemp("lead_meta.csv", csv);
  const auto j = nlohmann::json::parse(RunCli("analyze " + Q(f) + " --json").out);
  ASSERT_TRUE(j.contains("decomposition"));
  EXPECT_EQ(j["decomposition"]["lead_mm"], 10.0);
  EXPECT_TRUE(j["decomposition"]["harmonics"][0]["resolved"].get<bool>());  // 4 mm gaps < 5 mm
  const auto bad = RunCli("analyze " + Q(f) + " --lead-mm -3");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("lead_mm"), std::string::npos) << bad.err;
  std::string bad_csv = csv;
  bad_csv.replace(bad_csv.find("lead_mm: 10"), 11, "lead_mm: ten");
  const auto f2 = WriteTemp("lead_meta_bad.csv", bad_csv);
  const auto bad2 = RunCli("analyze " + Q(f2));
  EXPECT_EQ(bad2.exit_code, 2);
  EXPECT_NE(bad2.err.find(f2 + ":2: field 'lead_mm'"), std::string::npos) << bad2.err;
  std::filesystem::remove(f);
  std::filesystem::remove(f2);
}

struct BadInput {
  const char* name;
  std::string content;
  int line;            // expected line in the message (0: no line expected)
  const char* field;   // expected field in the message
};

class AnalyzeBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(AnalyzeBadInput, ExitsTwoNamingFileLineField) {
  const auto& p = GetParam();
  const auto f = WriteTemp(std::string("bad_") + p.name, p.content);
  const auto r = RunCli("analyze " + Q(f));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(f), std::string::npos) << r.err;
  if (p.line > 0) EXPECT_NE(r.err.find(f + ":" + std::to_string(p.line) + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(p.field), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  std::filesystem::remove(f);
}

namespace {
std::string TwoRuns() {
  return "1,+,0,1\n1,-,0,2\n1,+,10,1\n1,-,10,2\n2,+,0,1.1\n2,-,0,2.1\n2,+,10,1.1\n2,-,10,2.1\n";
}
}  // namespace

INSTANTIATE_TEST_SUITE_P(
    Issue2, AnalyzeBadInput,
    ::testing::Values(
        BadInput{"missing_column.csv", "run,direction,target_mm\n1,+,0\n", 1, "deviation_um"},
        BadInput{"non_numeric.csv", std::string(kGoodHeader) + "1,+,0,abc\n", 2, "deviation_um"},
        BadInput{"unknown_direction.csv", std::string(kGoodHeader) + "1,up-ish,0,1\n", 2, "direction"},
        BadInput{"duplicate.csv", std::string(kGoodHeader) + TwoRuns() + "2,+,10,5\n", 10, "target_mm"},
        BadInput{"one_direction.csv", std::string(kGoodHeader) + TwoRuns() + "1,+,20,1\n2,+,20,1\n", 10, "direction"},
        BadInput{"one_run.csv", std::string(kGoodHeader) + "1,+,0,1\n1,-,0,2\n", 2, "run"},
        BadInput{"empty.csv", "", 0, "header"},
        BadInput{"comments_only.csv", "# axis: X\n", 0, "header"},
        BadInput{"bad_ecmc_value.dat", "UNIT=mm\nTGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0.x1\n", 3, "REF_DATA_FWD[1,1]"},
        BadInput{"bad_ecmc_unit.dat", "UNIT=furlong\nTGT_DATA[1]=0\n", 1, "UNIT"},
        BadInput{"ecmc_missing_target.dat", "TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0\nREF_DATA_BWD[2,1]=0\n", 3,
                 "REF_DATA_BWD[2,1]"},
        BadInput{"ecmc_one_cycle.dat", "TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0\nREF_DATA_BWD[1,1]=0\n", 2, "run"},
        BadInput{"ecmc_empty.dat", "", 0, "TGT_DATA"}),
    [](const auto& info) {
      std::string n = info.param.name;
      for (auto& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

TEST(AnalyzeCli, MissingFileIsBadInput) {
  const auto r = RunCli("analyze /nonexistent/trueaxis.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/trueaxis.csv"), std::string::npos) << r.err;
}

TEST(AnalyzeCli, BadCompareFileAndUnwritableReportAreReported) {
  const auto bad = WriteTemp("bad_after.csv", std::string(kGoodHeader) + "1,+,0,x\n");
  const auto r = RunCli("analyze " + Q(kExample) + " --compare " + Q(bad));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad + ":2: field 'deviation_um'"), std::string::npos) << r.err;
  std::filesystem::remove(bad);
  const auto r2 = RunCli("analyze " + Q(kExample) + " --report /nonexistent-dir/x.html");
  EXPECT_NE(r2.exit_code, 0);
  EXPECT_NE(r2.err.find("/nonexistent-dir/x.html"), std::string::npos) << r2.err;
}

namespace {
// --compare of unrelated tests (0–800 mm 41×5 against a short-pitch run over a few leads) is
// refused, naming the files and the travel they cover, instead of a meaningless comparison.
TEST(AnalyzeCliCompare, UnrelatedTestsAreRefused) {
  const std::string dir = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/";
  const auto r = RunCli("analyze '" + dir + "x_axis_ballscrew_5x41.csv' --compare '" + dir + "x_axis_short_pitch.csv'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not a before/after of the same test"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("field 'target_mm'"), std::string::npos) << r.err;
}
}  // namespace

// `analyze run.csv --report run.csv` replaced the laser run with HTML (exit 0).
TEST(AnalyzeCli, ReportOverTheMeasurementIsRefused) {
  std::ifstream in(kExample);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string run = WriteTemp("analyze_over.csv", text);
  const auto r = RunCli("analyze " + Q(run) + " --report " + Q(run));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("command line: field '--report': '" + run + "' is the input file"), std::string::npos) << r.err;
  std::ifstream back(run);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(back)), std::istreambuf_iterator<char>()), text);
  std::filesystem::remove(run);
}
