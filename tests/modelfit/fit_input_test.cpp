// The fit's input checks: a campaign manifest and its temperature log are refused, naming the
// file, line and field, when they do not belong to the measurements they are given for.
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/modelfit/fit_input.hpp"

namespace trueaxis::model {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The one-file campaign (m.csv: nut 30 °C, start_time_s 10000 on the log's clock) with a log of
// rows every 50 s from `first_s` to `last_s` reading `nut_c`.
fs::path CampaignWithLog(const std::string& name, int first_s, int last_s, const std::string& nut_c,
                         const std::string& header = "time_s,date,coolant,t_nut_c") {
  const fs::path dir = testing::OneFileCampaignDir(name, "30");
  std::string log = header + "\n";
  for (int t = first_s; t <= last_s; t += 50) log += fmt::format("{},d,off,{}{}\n", t, nut_c,
                                                                  header.ends_with("t_nut_c,t_nut_c") ? "," + nut_c : "");
  WriteTextFile((dir / "temperature_log.csv").string(), log);
  return dir;
}

InputError LoadError(const fs::path& dir) {
  try {
    LoadFitStates({}, (dir / "manifest.json").string());
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << dir;
  return InputError("", "");
}

TEST(FitManifestLog, TheLogOfTheFilesCampaignIsAccepted) {
  const auto dir = CampaignWithLog("log_ok", 0, 10100, "30");
  EXPECT_EQ(LoadFitStates({}, (dir / "manifest.json").string()).size(), 1u);
  fs::remove_all(dir);
}

// fit --manifest checks the log as predict --temperature-log does (it took them all, exit 0).
TEST(FitManifestLog, AnotherCampaignsLogOrOneCutShortOrAStartOutsideItIsRefused) {
  const auto other = CampaignWithLog("log_other", 0, 10100, "35");  // reads 35 °C where the file reads 30
  auto e = LoadError(other);
  EXPECT_EQ(e.source(), (other / "temperature_log.csv").string());
  EXPECT_EQ(e.field(), "t_nut_c");
  EXPECT_GT(e.line(), 1);
  EXPECT_THAT(e.message(), HasSubstr("another campaign"));
  fs::remove_all(other);

  const auto cut = CampaignWithLog("log_cut", 0, 5000, "30");  // ends long before the file starts
  e = LoadError(cut);
  EXPECT_EQ(e.field(), "time_s");
  EXPECT_EQ(e.line(), 102);  // the log's last row: header + 101 rows
  EXPECT_THAT(e.message(), HasSubstr("the log ends at 5000 s"));
  fs::remove_all(cut);

  const auto late = CampaignWithLog("log_late", 20000, 30000, "30");  // starts after the file
  e = LoadError(late);
  EXPECT_EQ(e.field(), "time_s");
  EXPECT_THAT(e.message(), HasSubstr("the log starts at 20000 s"));
  fs::remove_all(late);
}

TEST(FitManifestLog, AColumnGivenTwiceIsRefused) {
  const auto dir = CampaignWithLog("log_dup", 0, 10100, "30", "time_s,date,coolant,t_nut_c,t_nut_c");
  const auto e = LoadError(dir);
  EXPECT_EQ(e.source(), (dir / "temperature_log.csv").string());
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.field(), "t_nut_c");
  EXPECT_THAT(e.message(), HasSubstr("column given twice (columns 4 and 5)"));
  fs::remove_all(dir);
}

// predict --temperature-log: a log without the model's key sensor would leave its lag without a
// history (A 5.5 → 28.7 µm on the sweep's campaign), silently.
TEST(FitManifestLog, ALogWithoutARequiredKeyColumnIsRefused) {
  const auto dir = CampaignWithLog("log_nokey", 0, 10100, "30");
  const auto m = measure::ReadMeasurementCsv((dir / "m.csv").string());
  const std::string log = (dir / "temperature_log.csv").string();
  EXPECT_NO_THROW(TemperatureHistoryFromLog(log, m, 10000, {"nut"}));
  try {
    TemperatureHistoryFromLog(log, m, 10000, {"nut", "bearing"});
    ADD_FAILURE() << "a log without t_bearing_c was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), log);
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.field(), "t_bearing_c");
  }
  fs::remove_all(dir);
}

void WriteManifest(const fs::path& dir, const std::string& entry, const std::string& head = "") {
  WriteTextFile((dir / "manifest.json").string(), "{" + head + R"("measurements": [{"file": "m.csv", )" + entry + "}]}");
}

// The manifest said axis Q for a file whose '# axis:' says X: the fit built a bogus axis Q.
TEST(FitManifest, AnAxisOrCoolantThatContradictsTheFileIsRefusedNamingTheEntry) {
  const auto dir = testing::OneFileCampaignDir("manifest_axis", "30");
  const std::string manifest = (dir / "manifest.json").string();
  WriteManifest(dir, R"("axis": "Q", "state": "warm")");
  auto e = LoadError(dir);
  EXPECT_EQ(e.source(), manifest);
  EXPECT_EQ(e.field(), "measurements[0].axis");
  EXPECT_THAT(e.message(), HasSubstr("line 1 says '# axis: X'"));
  WriteManifest(dir, R"("axis": "x", "state": "warm")");  // the same axis in lower case
  EXPECT_EQ(LoadFitStates({}, manifest).size(), 1u);

  // A bad coolant value is the manifest's, not the measurement file's.
  WriteManifest(dir, R"("axis": "X", "state": "warm", "coolant": "lava")");
  e = LoadError(dir);
  EXPECT_EQ(e.source(), manifest);
  EXPECT_EQ(e.field(), "measurements[0].coolant");
  EXPECT_THAT(e.message(), HasSubstr("unknown coolant state 'lava'"));

  // A coolant other than the file's own line.
  WriteTextFile((dir / "m.csv").string(), "# axis: X\n# coolant: off\nrun,direction,target_mm,deviation_um\n1,+,0,0\n1,+,100,0\n");
  WriteManifest(dir, R"("state": "coolant", "coolant": "flood")");
  e = LoadError(dir);
  EXPECT_EQ(e.field(), "measurements[0].coolant");
  EXPECT_THAT(e.message(), HasSubstr("line 2 says '# coolant: off'"));
  WriteManifest(dir, R"("state": "warm", "coolant": "off")");
  EXPECT_EQ(LoadFitStates({}, manifest).size(), 1u);
  fs::remove_all(dir);
}

TEST(FitManifest, AnotherFormatOrVersionIsRefused) {
  const auto dir = testing::OneFileCampaignDir("manifest_format", "30");
  WriteManifest(dir, R"("axis": "X", "state": "warm")", R"("format": "other", )");
  auto e = LoadError(dir);
  EXPECT_EQ(e.field(), "format");
  WriteManifest(dir, R"("axis": "X", "state": "warm")", R"("format": "trueaxis-sim-campaign", "version": 99, )");
  e = LoadError(dir);
  EXPECT_EQ(e.field(), "version");
  EXPECT_THAT(e.message(), HasSubstr("99 is not supported"));
  WriteManifest(dir, R"("axis": "X", "state": "warm")", R"("format": "trueaxis-sim-campaign", "version": 1, )");
  EXPECT_EQ(LoadFitStates({}, (dir / "manifest.json").string()).size(), 1u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::model
