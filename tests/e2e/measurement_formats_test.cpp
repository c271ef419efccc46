// Every command that takes a laser measurement reads every supported format through one reader:
// the same ecmc .dat gives the same results through analyze, convert, export, fit, predict and
// pitch table as its converted canonical CSV; a laser software's CSV export with a column mapping
// gives the same evaluation as its canonical equivalent; bad mappings exit 2 naming file, line and
// field.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_runner.hpp"
#include "support/shared_data.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace {

using trueaxis::testing::RunCli;
namespace fs = std::filesystem;

const std::string kSrc = TRUEAXIS_SOURCE_DIR;
const std::string kDat = std::string(TRUEAXIS_SHARED_DATA_DIR) + "/ecmc/fat_sat_test.dat";

class MeasurementFormats : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("trueaxis_formats_" + std::to_string(::getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
    return Path(name);
  }
  static std::string Read(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  // `analyze --json` of `args`; the test fails (and returns null) when it does not exit 0.
  static nlohmann::json Analyze(const std::string& args) {
    const auto r = RunCli("analyze --json " + args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    const auto brace = r.output.find('{');
    if (r.exit_code != 0 || brace == std::string::npos) return nullptr;
    return nlohmann::json::parse(r.output.substr(brace));
  }
  static void ExpectSameEvaluation(const nlohmann::json& a, const nlohmann::json& b) {
    ASSERT_FALSE(a.is_null());
    ASSERT_FALSE(b.is_null());
    for (const char* k : {"A_um", "R_um", "B_um", "E_um", "M_um", "runs", "positions"})
      EXPECT_EQ(a[k], b[k]) << k;
  }
  // Lines of a file without those naming where it came from.
  static std::string WithoutSources(const std::string& text) {
    std::istringstream in(text);
    std::string out, line;
    while (std::getline(in, line))
      if (line.find(".csv") == std::string::npos && line.find(".dat") == std::string::npos) out += line + "\n";
    return out;
  }

  fs::path dir_;
};

TEST_F(MeasurementFormats, EcmcDatGivesTheSameResultsThroughEveryCommandAsItsConvertedCsv) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kDat);
  const std::string csv = Path("fat_sat.csv");
  const auto conv = RunCli("measurement convert " + kDat + " --out " + csv + " --axis X --state cold");
  ASSERT_EQ(conv.exit_code, 0) << conv.output;
  EXPECT_NE(conv.output.find("ecmc .dat"), std::string::npos) << conv.output;
  const auto m = trueaxis::measure::ReadMeasurementCsv(csv);
  EXPECT_EQ(m.Meta("format").value_or(""), "ecmc dat");  // the ecmc keys are kept
  EXPECT_EQ(m.Meta("cycles").value_or(""), "5");
  EXPECT_EQ(m.Meta("state").value_or(""), "cold");
  EXPECT_EQ(m.points.size(), 50u);

  // analyze: the same ISO 230-2 figures from the .dat and from its canonical CSV.
  const auto from_dat = Analyze(kDat), from_csv = Analyze(csv);
  ExpectSameEvaluation(from_dat, from_csv);
  EXPECT_GT(from_dat["A_um"].get<double>(), 0);

  // export --measurement: the same table.
  const auto e1 = RunCli("export --measurement " + kDat + " --axis X --format csv --out " + Path("dat_table.csv"));
  ASSERT_EQ(e1.exit_code, 0) << e1.output;
  const auto e2 = RunCli("export --measurement " + csv + " --axis X --format csv --out " + Path("csv_table.csv"));
  ASSERT_EQ(e2.exit_code, 0) << e2.output;
  EXPECT_EQ(WithoutSources(Read(Path("dat_table.csv"))), WithoutSources(Read(Path("csv_table.csv"))));
  EXPECT_FALSE(WithoutSources(Read(Path("dat_table.csv"))).empty());

  // fit: a geometric-only fit of the cold run, state and axis from the options for the .dat.
  const auto f1 = RunCli("fit " + kDat + " --state cold --axis X --out " + Path("dat_model.json"));
  ASSERT_EQ(f1.exit_code, 0) << f1.output;
  const auto f2 = RunCli("fit " + csv + " --out " + Path("csv_model.json"));
  ASSERT_EQ(f2.exit_code, 0) << f2.output;
  for (const char* pos : {"-10", "0.24", "7.3"}) {
    const std::string at = std::string(" --axis X --position-mm ") + pos + " --direction + --geometric-only --json";
    const auto p1 = RunCli("predict --model " + Path("dat_model.json") + at);
    const auto p2 = RunCli("predict --model " + Path("csv_model.json") + at);
    ASSERT_EQ(p1.exit_code, 0) << p1.output;
    EXPECT_EQ(p1.output, p2.output) << pos;
  }

  // --state names the state of one file without one; for two it would make one state twice.
  const std::string other = std::string(TRUEAXIS_SHARED_DATA_DIR) + "/ecmc/mcu1025_fat_sat.dat";
  if (fs::exists(other)) {
    const auto two = RunCli("fit " + kDat + " " + other + " --state cold --axis X --out " + Path("two.json"));
    EXPECT_EQ(two.exit_code, 2) << two.output;
    EXPECT_NE(two.output.find("field '--state': 2 input files name no state"), std::string::npos) << two.output;
  }

  // predict --measurement on the .dat itself (held-out check path).
  const auto pm1 = RunCli("predict --model " + Path("dat_model.json") + " --measurement " + kDat + " --axis X --geometric-only");
  const auto pm2 = RunCli("predict --model " + Path("dat_model.json") + " --measurement " + csv + " --axis X --geometric-only");
  ASSERT_EQ(pm1.exit_code, 0) << pm1.output;
  EXPECT_EQ(WithoutSources(pm1.output), WithoutSources(pm2.output));

  // pitch table: the same pitch error file (a lead of twice the target spacing of 5.12 mm).
  const auto t1 = RunCli("pitch table --measurement " + kDat + " --lead-mm 10.24 --out " + Path("dat.pitch.csv"));
  const auto t2 = RunCli("pitch table --measurement " + csv + " --lead-mm 10.24 --out " + Path("csv.pitch.csv"));
  ASSERT_EQ(t1.exit_code, 0) << t1.output;
  ASSERT_EQ(t2.exit_code, 0) << t2.output;
  EXPECT_EQ(WithoutSources(Read(Path("dat.pitch.csv"))), WithoutSources(Read(Path("csv.pitch.csv"))));
  EXPECT_EQ(WithoutSources(t1.output), WithoutSources(t2.output));

  // convert refuses to write over its input.
  const auto over = RunCli("measurement convert " + csv + " --out " + csv);
  EXPECT_EQ(over.exit_code, 2) << over.output;
  EXPECT_NE(over.output.find("--out"), std::string::npos) << over.output;
}

// The example ball-screw test written as a laser software would: its own column names, up/down,
// a preamble, a column trueaxis does not use.
std::string VendorExport(const trueaxis::measure::Measurement& m) {
  std::string out = "Linear measurement export\n";
  out += "Point,Run,Dir,Target [mm],Error [µm],Time [s],Nut [°C],Bearing [°C],Air [°C],Flag\n";
  int i = 0;
  for (const auto& p : m.points) {
    out += std::to_string(++i) + "," + std::to_string(p.run) + "," +
           (p.direction == trueaxis::Direction::kForward ? "up" : "down");
    for (double v : {p.target_mm, p.deviation_um, p.time_s.value_or(0)}) {
      std::ostringstream s;
      s.precision(17);
      s << v;
      out += "," + s.str();
    }
    for (const char* sensor : {"nut", "bearing", "air"}) {
      std::ostringstream s;
      s.precision(17);
      s << p.temperatures_c[*m.SensorIndex(sensor)];
      out += "," + s.str();
    }
    out += ",ok\n";
  }
  return out;
}

TEST_F(MeasurementFormats, MappedVendorCsvEvaluatesAndFitsAsItsCanonicalEquivalent) {
  const std::string canonical = kSrc + "/examples/measurements/x_axis_ballscrew_5x41.csv";
  const auto m = trueaxis::measure::ReadMeasurementCsv(canonical);
  const std::string vendor = Write("laser_export.csv", VendorExport(m));
  const std::string map = Write("laser.toml",
                                "target_mm = \"Target [mm]\"\ndeviation_um = \"Error [µm]\"\nrun = \"Run\"\n"
                                "direction = \"Dir\"\ntime_s = \"Time [s]\"\nt_nut_c = \"Nut [°C]\"\n"
                                "t_bearing_c = \"Bearing [°C]\"\nt_air_c = \"Air [°C]\"\n"
                                "[metadata]\naxis = \"X\"\n");
  const std::string columns =
      "\"target_mm=Target [mm],deviation_um=Error [µm],run=Run,direction=Dir,time_s=Time [s],"
      "t_nut_c=Nut [°C],t_bearing_c=Bearing [°C],t_air_c=Air [°C]\"";

  // Without a mapping: refused, pointing at the mapping options.
  const auto bare = RunCli("analyze " + vendor);
  EXPECT_EQ(bare.exit_code, 2) << bare.output;
  EXPECT_NE(bare.output.find("--columns"), std::string::npos) << bare.output;

  const auto reference = Analyze(canonical);
  ExpectSameEvaluation(reference, Analyze(vendor + " --column-map " + map));
  ExpectSameEvaluation(reference, Analyze(vendor + " --columns " + columns));

  // convert → the canonical file; analysing it gives the same again.
  const auto conv = RunCli("measurement convert " + vendor + " --column-map " + map + " --out " + Path("conv.csv"));
  ASSERT_EQ(conv.exit_code, 0) << conv.output;
  EXPECT_NE(conv.output.find("mapped CSV"), std::string::npos) << conv.output;
  ExpectSameEvaluation(reference, Analyze(Path("conv.csv")));
  // An option contradicting the mapping's metadata is refused, not written over it.
  const auto clash = RunCli("measurement convert " + vendor + " --column-map " + map + " --axis Y --out " + Path("y.csv"));
  EXPECT_EQ(clash.exit_code, 2) << clash.output;
  EXPECT_NE(clash.output.find("field 'axis': the file says 'X', --axis says 'Y'"), std::string::npos) << clash.output;
  EXPECT_FALSE(fs::exists(Path("y.csv")));

  // fit with temperatures from the mapped columns: the same model as from the canonical file.
  const auto f1 = RunCli("fit " + canonical + " --state cold --out " + Path("c.json"));
  ASSERT_EQ(f1.exit_code, 0) << f1.output;
  const auto f2 = RunCli("fit " + vendor + " --column-map " + map + " --state cold --out " + Path("v.json"));
  ASSERT_EQ(f2.exit_code, 0) << f2.output;
  for (const char* pos : {"0", "123.4", "700"}) {
    const std::string at = std::string(" --axis X --position-mm ") + pos + " --direction - --geometric-only --json";
    const auto p1 = RunCli("predict --model " + Path("c.json") + at);
    ASSERT_EQ(p1.exit_code, 0) << p1.output;
    EXPECT_EQ(p1.output, RunCli("predict --model " + Path("v.json") + at).output) << pos;
  }
  // export --measurement and pitch table take the mapping too.
  const auto e1 = RunCli("export --measurement " + canonical + " --format csv --out " + Path("t1.csv"));
  const auto e2 = RunCli("export --measurement " + vendor + " --columns " + columns + " --format csv --out " + Path("t2.csv"));
  ASSERT_EQ(e1.exit_code, 0) << e1.output;
  ASSERT_EQ(e2.exit_code, 0) << e2.output;
  EXPECT_EQ(WithoutSources(Read(Path("t1.csv"))), WithoutSources(Read(Path("t2.csv"))));
  // (a 50 mm grid: the targets are up to 24.9 mm apart)
  const auto t1 = RunCli("pitch table --measurement " + canonical + " --lead-mm 50 --out " + Path("p1.csv"));
  const auto t2 = RunCli("pitch table --measurement " + vendor + " --column-map " + map + " --lead-mm 50 --out " + Path("p2.csv"));
  ASSERT_EQ(t1.exit_code, 0) << t1.output;
  ASSERT_EQ(t2.exit_code, 0) << t2.output;
  EXPECT_EQ(WithoutSources(Read(Path("p1.csv"))), WithoutSources(Read(Path("p2.csv"))));
}

TEST_F(MeasurementFormats, TheExampleLaserExportReadsAsTheExampleItWasMadeFrom) {
  const std::string ex = kSrc + "/examples/measurements/";
  ExpectSameEvaluation(Analyze(ex + "x_axis_cold.csv"),
                       Analyze(ex + "laser_export_x.csv --column-map " + ex + "laser_export.toml"));
}

TEST_F(MeasurementFormats, BadMappingsExitTwoNamingFileLineAndField) {
  const std::string vendor = Write("v.csv",
                                   "Run,Dir,Target [mm],Error [mm]\n1,up,0,0.001\n1,down,0,0.002\n2,sideways,0,0.001\n");
  const auto expect = [&](const std::string& args, const std::string& where) {
    for (const std::string cmd : {"analyze " + vendor, "fit " + vendor + " --out " + Path("m.json"),
                                  "export --format csv --out " + Path("t.csv") + " --measurement " + vendor,
                                  "pitch table --lead-mm 10 --out " + Path("p.csv") + " --measurement " + vendor,
                                  "measurement convert " + vendor + " --out " + Path("c.csv")}) {
      const auto r = RunCli(cmd + " " + args);
      EXPECT_EQ(r.exit_code, 2) << cmd << " " << args << "\n" << r.output;
      EXPECT_NE(r.output.find(where), std::string::npos) << cmd << " " << args << "\n" << r.output;
    }
  };
  // Unknown key: the option and the key.
  expect("--columns \"target=Target [mm]\"", "--columns: field 'target': unknown mapping key");
  // A mapped column the file does not have: the file, the header line and the column.
  expect("--columns \"target_mm=Target [mm],deviation_mm=Dev [mm],run=Run,direction=Dir\"",
         vendor + ":1: field 'Dev [mm]': mapped column");
  // Deviation written in mm under a µm mapping: refused at the header.
  expect("--columns \"target_mm=Target [mm],deviation_um=Error [mm],run=Run,direction=Dir\"",
         vendor + ":1: field 'Error [mm]': the column's name says mm");
  // An unrecognised direction word: its line and column.
  expect("--columns \"target_mm=Target [mm],deviation_mm=Error [mm],run=Run,direction=Dir\"",
         vendor + ":4: field 'Dir': 'sideways' is not a direction");
  // No run column: what is needed.
  expect("--columns \"target_mm=Target [mm],deviation_mm=Error [mm],direction=Dir\"", "map run=<column>");
  // A mapping file's misspelt key: the file, its line and the key.
  const std::string map = Write("bad.toml", "target_mm = \"Target [mm]\"\ndeviaton_mm = \"Error [mm]\"\n");
  expect("--column-map " + map, map + ":2: field 'deviaton_mm'");
}

}  // namespace
