// End-to-end tests of `trueaxis fit` and `trueaxis predict` through the real
// binary (TRUEAXIS_CLI_PATH), including the bad inputs a user will make.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include <gmock/gmock.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "synthetic_machine.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"

namespace trueaxis::model {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct Run {
  int code;
  std::string out;
};

Run Cli(const std::string& args) {
  const std::string cmd = std::string(TRUEAXIS_CLI_PATH) + " " + args + " 2>&1";
  FILE* f = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, f)) out.append(buf, n);
  const int status = pclose(f);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class CliFit : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fs::path("trueaxis_cli_fit_" + std::to_string(::getpid()) + "_" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    testing::SyntheticMachine sm;
    std::mt19937 rng(5);
    for (const auto& s : sm.DefaultStates()) {
      auto m = sm.Make(s, rng);
      const std::string path = (dir_ / (s.label + ".csv")).string();
      measure::WriteMeasurementCsv(m, path);
      files_.push_back(path);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string P(const std::string& name) const { return (dir_ / name).string(); }
  std::string AllFiles() const {
    std::string s;
    for (const auto& f : files_) s += " " + f;
    return s;
  }
  fs::path dir_;
  std::vector<std::string> files_;
};

TEST_F(CliFit, LagOptionsAreCheckedAndTheTemperatureLogNeedsTheFilesStart) {
  auto bad = Cli("fit --out " + P("m.json") + " --lag-grid-s 0,-60" + AllFiles());
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_THAT(bad.out, HasSubstr("key_lag_grid_s"));
  auto r = Cli("fit --out " + P("m.json") + " --lag-grid-s 0" + AllFiles());
  ASSERT_EQ(r.code, 0) << r.out;
  WriteTextFile(P("log.csv"), "time_s,t_nut_c\n0,20\n");
  // The synthetic files have no '# campaign_time_s:' line: the log cannot be placed.
  auto p = Cli("predict --model " + P("m.json") + " --measurement " + files_[2] + " --temperature-log " + P("log.csv"));
  EXPECT_EQ(p.code, 2) << p.out;
  EXPECT_THAT(p.out, HasSubstr("campaign_time_s"));
}

TEST_F(CliFit, FitWritesModelReportAndPredictUsesIt) {
  auto r = Cli("fit --out " + P("m.json") + " --report " + P("fit.html") + AllFiles());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("keys"));
  const auto m = ReadModelFile(P("m.json"));
  ASSERT_EQ(m.axes.size(), 1u);
  EXPECT_EQ(m.revision, 1);
  EXPECT_EQ(m.sources.size(), 6u);
  EXPECT_EQ(m.sources[0].sha256, Sha256OfFile(files_[0]));
  const std::string html = ReadTextFile(P("fit.html"));
  EXPECT_THAT(html, HasSubstr("<svg"));
  EXPECT_THAT(html, HasSubstr("heated-4"));

  auto p = Cli("predict --model " + P("m.json") +
               " --axis X --position-mm 400 --direction + --temp nut=26,bearing=23,ambient=20 --json");
  ASSERT_EQ(p.code, 0) << p.out;
  auto j = nlohmann::json::parse(p.out);
  // The library's prediction for the same state, and correction = −error.
  const double temps[] = {26, 23};
  std::vector<double> t;
  for (const auto& k : m.axes[0].key_sensors) t.push_back(k == "nut" ? temps[0] : temps[1]);
  auto lib = Predict(m.axes[0], 400, Direction::kForward, {t, 20.0, CoolantState::kOff, true});
  EXPECT_NEAR(j["error_um"].get<double>(), lib.total_um, 1e-9);
  EXPECT_NEAR(j["correction_um"].get<double>(), -lib.total_um, 1e-9);
  auto text = Cli("predict --model " + P("m.json") +
                  " --axis X --position-mm 400 --direction - --temp nut=26,bearing=23 --ambient-c 20");
  ASSERT_EQ(text.code, 0) << text.out;
  EXPECT_THAT(text.out, HasSubstr("correction (added to the command)"));
  // Without the ambient reading the prediction would silently change (ρ term dropped, key rises
  // no longer above ambient): the fallback fitted without the room sensor predicts when its keys
  // are given, and says so, as the compensator does when the room sensor is lost ...
  const AxisModel* without_room = nullptr;
  for (const auto& f : m.axes[0].fallbacks)
    if (f.replaces == "ambient") without_room = &f;
  ASSERT_NE(without_room, nullptr);
  const std::map<std::string, double> reading{{"nut", 26}, {"bearing", 23}, {"motor", 27}};
  std::string room_keys;
  for (const auto& k : without_room->key_sensors) room_keys += fmt::format("{}{}={}", room_keys.empty() ? "" : ",", k, reading.at(k));
  auto no_ambient = Cli("predict --model " + P("m.json") + " --axis X --position-mm 400 --direction - --temp " + room_keys);
  EXPECT_EQ(no_ambient.code, 0) << no_ambient.out;
  EXPECT_THAT(no_ambient.out, HasSubstr("ambient (--ambient-c) not given: the fallback model fitted without it"));
  // ... and a model without fallbacks refuses, naming the option and the baseline.
  ASSERT_EQ(Cli("fit --no-fallback-models --out " + P("bare.json") + AllFiles()).code, 0);
  no_ambient = Cli("predict --model " + P("bare.json") + " --axis X --position-mm 400 --direction - --temp nut=26,bearing=23");
  EXPECT_EQ(no_ambient.code, 2) << no_ambient.out;
  EXPECT_THAT(no_ambient.out, HasSubstr("--ambient-c"));
  // Kelvin (or a lost decimal point) is refused, not turned into a millimetre correction.
  auto kelvin = Cli("predict --model " + P("m.json") +
                    " --axis X --position-mm 400 --direction + --temp nut=299.2,bearing=296.2 --ambient-c 20");
  EXPECT_EQ(kelvin.code, 2) << kelvin.out;
  EXPECT_THAT(kelvin.out, HasSubstr("looks like kelvin"));
  // Plausible but beyond the fit's temperatures: predicted, with a warning and the JSON flag.
  auto hot = Cli("predict --model " + P("m.json") +
                 " --axis X --position-mm 400 --direction + --temp nut=80,bearing=23 --ambient-c 20");
  EXPECT_EQ(hot.code, 0) << hot.out;
  EXPECT_THAT(hot.out, HasSubstr("nut 80 °C is outside the fitted"));
  auto hot_json = Cli("predict --model " + P("m.json") +
                      " --axis X --position-mm 400 --direction + --temp nut=80,bearing=23 --ambient-c 20 --json");
  ASSERT_EQ(hot_json.code, 0) << hot_json.out;
  EXPECT_EQ(nlohmann::json::parse(hot_json.out)["temperatures_outside_fitted_range"].size(), 1u);
  // A room colder than any state of the fit: the room term extrapolated, said so.
  ASSERT_TRUE(std::isfinite(m.axes[0].ambient_fitted_range_c[0])) << "the fit records the room's range";
  const std::string cold_room = fmt::format("{:.1f}", m.axes[0].ambient_fitted_range_c[0] - 2);
  auto cold = Cli("predict --model " + P("m.json") + " --axis X --position-mm 400 --direction + --temp nut=26,bearing=23 --ambient-c " +
                  cold_room + " --json");
  ASSERT_EQ(cold.code, 0) << cold.out;
  const auto outside = nlohmann::json::parse(cold.out)["temperatures_outside_fitted_range"];
  ASSERT_EQ(outside.size(), 1u) << cold.out;
  EXPECT_THAT(outside[0].get<std::string>(), HasSubstr("ambient " + cold_room + " °C is outside the fitted"));
  auto lost_point = Cli("predict --model " + P("m.json") +
                        " --axis X --position-mm 400 --direction + --temp nut=2820,bearing=23 --ambient-c 20");
  EXPECT_EQ(lost_point.code, 2) << lost_point.out;
}

// The room term from the feedback's CTE on the command line: ρ = −cte/1000, a CTE the room changes
// contradict is warned about, an absurd one refused; --rho-fit fits it from the room instead.
TEST_F(CliFit, CteOptionGivesTheSoakAndRhoFitTheRoomsFit) {
  auto r = Cli("fit --out " + P("cte.json") + " --cte 30" + AllFiles());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NEAR(ReadModelFile(P("cte.json")).axes[0].rho_um_per_mm_per_c, -0.030, 1e-12);
  EXPECT_THAT(r.out, HasSubstr("check the CTE"));
  auto fitted = Cli("fit --out " + P("fitted.json") + " --cte 30 --rho-fit" + AllFiles());
  ASSERT_EQ(fitted.code, 0) << fitted.out;
  EXPECT_GT(std::abs(ReadModelFile(P("fitted.json")).axes[0].rho_um_per_mm_per_c + 0.030), 0.005) << fitted.out;
  auto absurd = Cli("fit --out " + P("absurd.json") + " --cte 11500" + AllFiles());
  EXPECT_EQ(absurd.code, 2) << absurd.out;
  EXPECT_THAT(absurd.out, HasSubstr("cte_um_per_m_c"));
  EXPECT_FALSE(fs::exists(P("absurd.json")));
}

TEST_F(CliFit, TheSameFileTwiceIsRefusedNotCountedTwice) {
  const auto files = AllFiles();
  const auto first = files.substr(0, files.find(".csv") + 4);
  auto r = Cli("fit --out " + P("m.json") + files + first);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("given twice"));
}

TEST_F(CliFit, KeysOptionLeavesTheFilesAfterItPositional) {
  auto r = Cli("fit --out " + P("m.json") + " --keys nut,bearing" + AllFiles());
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST_F(CliFit, PredictMeasurementReportsHeldOutResidual) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  // Another day of the same synthetic machine, not used in the fit.
  testing::SyntheticMachine day2;
  std::mt19937 rng(77);
  auto m = day2.Make({"heated-x", 5.0, 2.2, 3.0, 1.5}, rng);
  measure::WriteMeasurementCsv(m, P("day2.csv"));
  auto r = Cli("predict --model " + P("m.json") + " --measurement " + P("day2.csv") + " --residual-out " + P("res.csv"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("measured − predicted  ISO 230-2 A"));
  const auto res = measure::ReadMeasurementCsv(P("res.csv"));
  const auto model = ReadModelFile(P("m.json"));
  ASSERT_EQ(res.points.size(), m.points.size());
  for (std::size_t i = 0; i < m.points.size(); i += 37) {
    const auto t = TemperaturesForPoint(model.axes[0], m, m.points[i]);
    const double pred = Predict(model.axes[0], m.points[i].target_mm, m.points[i].direction,
                                {t.key_temp_c, t.ambient_c, CoolantState::kOff, true}).total_um;
    EXPECT_NEAR(res.points[i].deviation_um, m.points[i].deviation_um - pred, 1e-6);
  }
  // A file without the model's key sensors is refused, naming the column.
  m.sensor_names = {"ambient"};
  for (auto& p : m.points) p.temperatures_c = {20};
  measure::WriteMeasurementCsv(m, P("nokeys.csv"));
  r = Cli("predict --model " + P("m.json") + " --measurement " + P("nokeys.csv"));
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("t_nut_c"));
}

// `fit … --out <a measurement>` replaced the raw laser file by model JSON (exit 0). --previous may be
// --out: it is read in full first, and the new revision records it as parent (docs/model-file.md).
TEST_F(CliFit, RefusesAnOutputOverAnInputButMayReplaceThePreviousRevision) {
  const std::string measurement = ReadTextFile(files_[0]);
  auto r = Cli("fit --out " + files_[0] + AllFiles());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("command line: field '--out': '" + files_[0] + "' is the input file"));
  EXPECT_EQ(ReadTextFile(files_[0]), measurement);
  r = Cli("fit --out " + P("m.json") + " --report " + files_[1] + AllFiles());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("field '--report'"));
  EXPECT_FALSE(fs::exists(P("m.json")));
  r = Cli("fit --out " + P("m.json") + " --report " + P("m.json") + AllFiles());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("field '--report'"));
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const std::string first_sha = Sha256OfFile(P("m.json"));
  r = Cli("fit --out " + P("m.json") + " --previous " + P("m.json") + AllFiles());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto m2 = ReadModelFile(P("m.json"));
  EXPECT_EQ(m2.revision, 2);
  EXPECT_EQ(m2.parent_sha256, first_sha);
}

TEST_F(CliFit, RefitRecordsRevisionParentAndLineage) {
  ASSERT_EQ(Cli("fit --out " + P("m1.json") + AllFiles()).code, 0);
  auto r2 = Cli("fit --out " + P("m2.json") + " --previous " + P("m1.json") + AllFiles());
  ASSERT_EQ(r2.code, 0) << r2.out;
  EXPECT_THAT(r2.out, HasSubstr("changes against revision 1"));
  ASSERT_EQ(Cli("fit --out " + P("m3.json") + " --previous " + P("m2.json") + AllFiles()).code, 0);
  const auto m3 = ReadModelFile(P("m3.json"));
  EXPECT_EQ(m3.revision, 3);
  EXPECT_EQ(m3.parent_sha256, Sha256OfFile(P("m2.json")));
  ASSERT_EQ(m3.lineage.size(), 2u);
  EXPECT_EQ(m3.lineage[0].revision, 1);
  EXPECT_EQ(m3.lineage[0].sha256, Sha256OfFile(P("m1.json")));
  EXPECT_EQ(m3.lineage[1].revision, 2);
}

TEST_F(CliFit, AddToPreviousRefitsOnOldSourcesPlusNewOnes) {
  // First fit without the last heated state, then add it.
  std::string first;
  for (const auto& f : files_)
    if (f.find("heated-4") == std::string::npos) first += " " + f;
  ASSERT_EQ(Cli("fit --out " + P("m1.json") + first).code, 0);
  auto r = Cli("fit --out " + P("m2.json") + " --previous " + P("m1.json") + " --add-to-previous " + P("heated-4.csv") +
               " " + files_[0]);  // cold given again: not counted twice
  ASSERT_EQ(r.code, 0) << r.out;
  const auto m2 = ReadModelFile(P("m2.json"));
  EXPECT_EQ(m2.revision, 2);
  EXPECT_EQ(m2.sources.size(), 6u);
  EXPECT_EQ(m2.sources.back().state, "heated-4");
  EXPECT_EQ(m2.sources.front().state, "cold");
  EXPECT_EQ(m2.sources.front().coolant, "off");
  // A source that changed since the previous fit is refused, naming it.
  auto cold = measure::ReadMeasurementCsv(files_[0]);
  cold.points[0].deviation_um += 1;
  measure::WriteMeasurementCsv(cold, files_[0]);
  r = Cli("fit --out " + P("m3.json") + " --previous " + P("m2.json") + " --add-to-previous");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr(files_[0]));
  EXPECT_THAT(r.out, HasSubstr("changed since the previous fit"));
  r = Cli("fit --out " + P("m3.json") + " --add-to-previous " + files_[1]);
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("--previous"));
}

TEST_F(CliFit, ManifestListsFilesWithTheirStates) {
  // States from the manifest only: strip the '# state:' lines from the files.
  nlohmann::json man = {{"files", nlohmann::json::array()}};
  for (const auto& f : files_) {
    auto m = measure::ReadMeasurementCsv(f);
    const std::string state = *m.Meta("state");
    std::erase_if(m.metadata, [](const auto& kv) { return kv.first == "state"; });
    measure::WriteMeasurementCsv(m, f);
    man["files"].push_back({{"path", fs::path(f).filename().string()}, {"state", state}});
  }
  WriteTextFile(P("manifest.json"), man.dump(2));
  auto r = Cli("fit --out " + P("m.json") + " --manifest " + P("manifest.json") + " --full");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("cold state: " + P("cold.csv")));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("no file is marked")));
}

TEST_F(CliFit, BadInputsExitWithFileLineField) {
  // Degenerate positions in the cold file.
  auto m = measure::ReadMeasurementCsv(files_[0]);
  for (auto& p : m.points) p.target_mm = 50;
  measure::WriteMeasurementCsv(m, P("flat.csv"));
  auto r = Cli("fit --out " + P("x.json") + " " + P("flat.csv"));
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr(P("flat.csv") + ":"));
  EXPECT_THAT(r.out, HasSubstr("target_mm"));
  EXPECT_FALSE(fs::exists(P("x.json")));

  // A heated state with no temperature columns.
  auto h = measure::ReadMeasurementCsv(files_[2]);
  h.sensor_names.clear();
  for (auto& p : h.points) p.temperatures_c.clear();
  measure::WriteMeasurementCsv(h, files_[2]);
  r = Cli("fit --out " + P("x.json") + AllFiles());
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("heated-2.csv"));
  EXPECT_THAT(r.out, HasSubstr("no temperature columns"));

  // Options: each bad value refused (exit 2), naming the option or the field it sets.
  const std::pair<std::string, std::string> bad_options[] = {
      {"--geometric spline", "--geometric"},
      {"--max-degree 0", "max_degree"},
      {"--key-offsets sometimes", "--key-offsets"},
      {"--secondary-key-ridge -1", "secondary_key_ridge"},
      {"--lag-fall-grid 1,0.5", "key_lag_fall_grid"}};
  for (const auto& [option, named] : bad_options) {
    r = Cli("fit --out " + P("x.json") + " " + option + " " + files_[0]);
    EXPECT_EQ(r.code, 2) << option;
    EXPECT_THAT(r.out, HasSubstr(named)) << option;
  }
  r = Cli("fit --out " + P("x.json"));
  EXPECT_EQ(r.code, 2);

  // Manifest: not JSON (line named), and a listed file that does not exist.
  WriteTextFile(P("bad.json"), "{\n  \"files\": [\n    \"cold.csv\",,\n  ]\n}\n");
  r = Cli("fit --out " + P("x.json") + " --manifest " + P("bad.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr(P("bad.json") + ":3:"));
  WriteTextFile(P("missing.json"), R"({"files": [{"path": "nope.csv", "state": "cold"}]})");
  r = Cli("fit --out " + P("x.json") + " --manifest " + P("missing.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("nope.csv"));

  // A previous model that is not a model.
  WriteTextFile(P("prev.json"), R"({"format": "something-else"})");
  r = Cli("fit --out " + P("x.json") + " --previous " + P("prev.json") + " " + files_[0]);
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("format"));
  EXPECT_FALSE(fs::exists(P("x.json")));
}

// The cold file's CTE and Px metadata: 1e308 gave ρ = −1e305 and residuals of inf (exit 0), 1e6 mm a
// Px a kilometre away; refused with the file's line. A negative CTE (Invar can have one, a sign
// error more likely) gives ρ > 0 with a warning.
TEST_F(CliFit, AbsurdCteOrReferenceMetadataIsRefusedANegativeCteWarned) {
  std::string without_ambient;  // the room constant: ρ comes from the CTE
  for (const auto& f : files_)
    if (f.find("ambient") == std::string::npos) without_ambient += " " + f;
  auto cold = measure::ReadMeasurementCsv(files_[0]);
  const auto with_meta = [&](const std::string& key, const std::string& value) {
    auto m = cold;
    m.SetMeta(key, value);
    measure::WriteMeasurementCsv(m, files_[0]);
    return measure::ReadMeasurementCsv(files_[0]).MetaLine(key);
  };
  int line = with_meta("cte_um_per_m_c", "1e308");
  auto r = Cli("fit --out " + P("m.json") + without_ambient);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr(fmt::format("{}:{}: field 'cte_um_per_m_c': 1e+308 µm/m/°C is beyond", files_[0], line)));
  EXPECT_FALSE(fs::exists(P("m.json")));
  line = with_meta("reference_position_mm", "1e6");
  r = Cli("fit --out " + P("m.json") + without_ambient);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr(fmt::format("{}:{}: field 'reference_position_mm': 1000000 mm is beyond", files_[0], line)));
  cold = measure::ReadMeasurementCsv(files_[0]);
  std::erase_if(cold.metadata, [](const auto& kv) { return kv.first == "reference_position_mm"; });
  line = with_meta("cte_um_per_m_c", "-11.5");
  r = Cli("fit --out " + P("m.json") + without_ambient);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr(fmt::format("{} line {}: cte_um_per_m_c -11.5 µm/m/°C is negative", files_[0], line)));
  EXPECT_NEAR(ReadModelFile(P("m.json")).axes[0].rho_um_per_mm_per_c, 0.0115, 1e-12);
}

// predict --temp: a sensor given twice took the last value, and --temp <room>=30 with --ambient-c 20
// took 20, silently.
TEST_F(CliFit, PredictRefusesATemperatureGivenTwice) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const std::string at = "predict --model " + P("m.json") + " --axis X --position-mm 400 --direction + ";
  auto r = Cli(at + "--temp nut=26,bearing=23,nut=30 --ambient-c 20");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("command line: field '--temp': sensor 'nut' given twice"));
  r = Cli(at + "--temp nut=26,bearing=23,ambient=30 --ambient-c 20");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("field '--ambient-c': 20 °C, but --temp ambient=30"));
  r = Cli(at + "--temp nut=26,bearing=23,ambient=20 --ambient-c 20");  // the same value twice: no conflict
  EXPECT_EQ(r.code, 0) << r.out;
}

// predict --temperature-log with a log that lacks the model's key sensor: the lag went without its
// history (A 5.5 → 28.7 µm on a campaign's day), silently; refused naming the log and the column.
TEST_F(CliFit, PredictRefusesATemperatureLogWithoutTheKeySensorsColumn) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const std::string key = ReadModelFile(P("m.json")).axes[0].key_sensors.at(0);
  auto day = measure::ReadMeasurementCsv(files_[2]);
  day.SetMeta("campaign_time_s", "1000");
  measure::WriteMeasurementCsv(day, P("day.csv"));
  std::string log = "time_s,t_other_c\n";
  for (int t = 0; t <= 5000; t += 60) log += fmt::format("{},20\n", t);
  WriteTextFile(P("log.csv"), log);
  auto r = Cli("predict --model " + P("m.json") + " --measurement " + P("day.csv") + " --temperature-log " + P("log.csv"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr(P("log.csv") + ":1: field 't_" + key + "_c': the log has no column"));
}

// Without a key sensor's temperature, predict takes the model's fallbacks fitted without it whose
// keys are all given (as the compensator does when that sensor is lost), says so, and gives the mean
// of their predictions.
TEST_F(CliFit, PredictUsesAFallbackModelWhenAKeySensorIsNotGiven) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const auto model = ReadModelFile(P("m.json"));
  const std::map<std::string, double> reading{{"bearing", 21.5}, {"motor", 26.5}};  // no nut
  std::vector<const AxisModel*> without_nut;
  for (const auto& f : model.axes[0].fallbacks)
    if (f.replaces == "nut") without_nut.push_back(&f);
  ASSERT_EQ(without_nut.size(), 2u) << "re-chosen keys and the model's other key";
  double expected = 0;
  for (const auto* f : without_nut) {
    std::vector<double> keys;
    for (const auto& k : f->key_sensors) keys.push_back(reading.at(k));
    expected += Predict(*f, 400, Direction::kForward, {keys, 20.0, CoolantState::kOff, true}).total_um / 2;
  }
  const std::string cmd = "predict --model " + P("m.json") +
                          " --axis X --position-mm 400 --direction + --ambient-c 20 --temp bearing=21.5,motor=26.5";
  auto r = Cli(cmd);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("nut not given: the mean of the 2 fallback models fitted without it"));
  r = Cli(cmd + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["fallback_model"].get<std::vector<std::string>>(), without_nut[0]->key_sensors);
  EXPECT_EQ(j["fallback_models_averaged"].get<int>(), 2);
  EXPECT_NEAR(j["error_um"].get<double>(), expected, 1e-9);
  // With only the bearing given, the one whose keys are given alone.
  const AxisModel* bearing_only = without_nut[0]->key_sensors == std::vector<std::string>{"bearing"} ? without_nut[0] : without_nut[1];
  ASSERT_EQ(bearing_only->key_sensors, std::vector<std::string>{"bearing"});
  r = Cli("predict --model " + P("m.json") + " --axis X --position-mm 400 --direction + --ambient-c 20 --json --temp bearing=21.5");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto alone = nlohmann::json::parse(r.out);
  EXPECT_EQ(alone["fallback_models_averaged"].get<int>(), 1);
  const double t_b[] = {21.5};
  EXPECT_NEAR(alone["error_um"].get<double>(),
              Predict(*bearing_only, 400, Direction::kForward, {t_b, 20.0, CoolantState::kOff, true}).total_um, 1e-9);
  const std::string temps = "bearing=21.5,motor=26.5";
  // With every key of the model given, the model itself (no fallback); a sensor only a fallback
  // reads is named as unused, not dropped silently.
  r = Cli("predict --model " + P("m.json") + " --axis X --position-mm 400 --direction + --ambient-c 20 --json --temp nut=24.5,bearing=21.5,motor=26.5");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto own = nlohmann::json::parse(r.out);
  EXPECT_TRUE(own["fallback_model"].is_null());
  EXPECT_EQ(own["unused_sensors"].get<std::vector<std::string>>(), std::vector<std::string>{"motor"});
  r = Cli("predict --model " + P("m.json") + " --axis X --position-mm 400 --direction + --ambient-c 20 --temp nut=24.5,bearing=21.5,motor=26.5");
  EXPECT_THAT(r.out, HasSubstr("motor is not used by this model"));
  // fit --no-fallback-models writes none, and then a missing key is refused as before.
  ASSERT_EQ(Cli("fit --no-fallback-models --out " + P("none.json") + AllFiles()).code, 0);
  EXPECT_TRUE(ReadModelFile(P("none.json")).axes[0].fallbacks.empty());
  r = Cli("predict --model " + P("none.json") + " --axis X --position-mm 400 --direction + --ambient-c 20 --temp " + temps);
  EXPECT_EQ(r.code, 2) << r.out;
  // fit --redundant: the fallback without the nut does without its partner (here the bearing
  // stands in for a second probe on the nut); a name the files lack, or a lone name, is refused.
  r = Cli("fit --redundant nut,bearing --out " + P("pair.json") + AllFiles());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("(and its redundant bearing)"));
  const auto paired = ReadModelFile(P("pair.json"));
  for (const auto& f : paired.axes[0].fallbacks)
    if (std::find(f.key_sensors.begin(), f.key_sensors.end(), "nut") == f.key_sensors.end())
      EXPECT_THAT(f.key_sensors, ::testing::Not(::testing::Contains("bearing")));
  r = Cli("fit --redundant nut,nut_b --out " + P("bad.json") + AllFiles());
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("field '--redundant': 'nut_b' is not a sensor of the measurement files"));
  EXPECT_EQ(Cli("fit --redundant nut --out " + P("bad.json") + AllFiles()).code, 2);
}

// A laser file whose nut channel died (the column empty): predict --measurement takes the fallback
// fitted without the nut, says so, and its residual is measured − that fallback's prediction.
TEST_F(CliFit, PredictMeasurementWithADeadKeyChannelUsesTheFallback) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const auto model = ReadModelFile(P("m.json"));
  const AxisModel* without_nut = nullptr;
  for (const auto& f : model.axes[0].fallbacks)
    if (std::find(f.key_sensors.begin(), f.key_sensors.end(), "nut") == f.key_sensors.end()) without_nut = &f;
  ASSERT_NE(without_nut, nullptr);
  testing::SyntheticMachine day2;
  std::mt19937 rng(78);
  auto m = day2.Make({"heated-x", 5.0, 2.2, 3.0, 1.5}, rng);
  const auto nut = *m.SensorIndex("nut");
  for (auto& pt : m.points) pt.temperatures_c[nut] = std::nan("");
  measure::WriteMeasurementCsv(m, P("dead_nut.csv"));
  // The second fallback's Er(x) moved by 5 µm: as the compensator, the residual keeps the first
  // one's Er(x) and averages only the thermal + room parts.
  auto shifted = model;
  std::vector<AxisModel*> group;  // the fallbacks replacing the nut, in file order
  for (auto& f : shifted.axes[0].fallbacks)
    if (f.replaces == "nut") group.push_back(&f);
  ASSERT_EQ(group.size(), 2u);
  EXPECT_TRUE(group[0]->key_sensors == without_nut->key_sensors || group[1]->key_sensors == without_nut->key_sensors);
  for (auto& d : group[1]->directions) {
    ASSERT_EQ(d.geometric.kind, GeometricError::Kind::kPolynomial);
    d.geometric.coefficients_um[0] += 5;
  }
  WriteModelFile(shifted, P("shifted.json"));
  const auto r = Cli("predict --model " + P("shifted.json") + " --measurement " + P("dead_nut.csv") + " --residual-out " + P("res.csv"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("nut not read in this file: predicted with the mean of the 2 fallback models"));
  const auto res = measure::ReadMeasurementCsv(P("res.csv"));
  for (std::size_t i = 0; i < m.points.size(); i += 41) {
    const auto& pt = m.points[i];
    double pred = 0;
    for (const auto* f : group) {
      const auto t = TemperaturesForPoint(*f, m, pt);
      const auto p = Predict(*f, pt.target_mm, pt.direction, {t.key_temp_c, t.ambient_c, CoolantState::kOff, true});
      pred += (p.total_um - p.geometric_um) / 2;
    }
    pred += group[0]->For(pt.direction).geometric.Evaluate(pt.target_mm);
    EXPECT_NEAR(res.points[i].deviation_um, pt.deviation_um - pred, 1e-6);
  }
}

TEST_F(CliFit, PredictRejectsMissingOrUnknownInputs) {
  ASSERT_EQ(Cli("fit --out " + P("m.json") + AllFiles()).code, 0);
  const std::string base = "predict --model " + P("m.json") + " --position-mm 100 ";
  auto r = Cli(base + "--axis X --direction + --temp nut=25");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("bearing"));
  r = Cli(base + "--axis Q --direction + --geometric-only");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("no axis 'Q'"));
  r = Cli(base + "--axis X --direction up --geometric-only");
  EXPECT_EQ(r.code, 0) << r.out;  // "up" is a documented spelling of forward
  r = Cli(base + "--axis X --direction sideways --geometric-only");
  EXPECT_EQ(r.code, 2);
  r = Cli(base + "--axis X --direction + --temp nut=hot,bearing=22");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("'hot'"));
  r = Cli(base + "--axis X --direction + --temp spindle=30 --geometric-only");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.out, HasSubstr("not a key sensor"));
  r = Cli(base + "--axis X --direction + --coolant lava --geometric-only");
  EXPECT_EQ(r.code, 2);
  r = Cli(base + "--axis X --direction - --geometric-only");
  EXPECT_EQ(r.code, 0) << r.out;
}

}  // namespace
}  // namespace trueaxis::model

namespace trueaxis::model {
namespace {

// `fit` on a small virtual campaign (sim campaign, one axis) prints the residual block: per state
// held out (each dry state predicted by the gains fitted without it), a finding in plain words and
// the key sensors' shares; the HTML report has its section.
TEST_F(CliFit, FitPrintsWhatTheResidualShowsForACampaign) {
  const std::string machine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc400_small.toml";
  auto c = Cli("sim campaign --quiet --machine " + machine + " --out " + P("camp") +
               " --axes X --runs 2 --warm-runs 2 --spacing-mm 100 --max-warm 4 --max-coolant 2 --cooldown 1"
               " --ambient-days 60 --ambient-hours 10");
  ASSERT_EQ(c.code, 0) << c.out;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(P("camp")))
    if (e.path().extension() == ".csv" && e.path().filename().string().rfind("X_", 0) == 0) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u);
  std::string args;
  for (const auto& f : files) args += " " + f;
  auto r = Cli("fit --out " + P("m.json") + " --report " + P("fit.html") + args);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("residual (cross-validated; noise levels: offset"));
  EXPECT_THAT(r.out, HasSubstr("held-out residual"));
  EXPECT_THAT(r.out, HasSubstr("key sensor share of the thermal correction:"));
  EXPECT_TRUE(r.out.find("no structure:") != std::string::npos || r.out.find("slope: in ") != std::string::npos ||
              r.out.find("offset: in ") != std::string::npos)
      << r.out;
  auto full = Cli("fit --full --out " + P("m2.json") + args);
  ASSERT_EQ(full.code, 0) << full.out;
  EXPECT_THAT(full.out, HasSubstr("residual shape per state (cross-validated"));
  EXPECT_THAT(full.out, HasSubstr("warm-01"));
  const std::string html = ReadTextFile(P("fit.html"));
  EXPECT_THAT(html, HasSubstr("What the residual shows"));
  EXPECT_THAT(html, HasSubstr("share of the thermal correction"));
}

}  // namespace
}  // namespace trueaxis::model
