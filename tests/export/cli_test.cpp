// The `trueaxis export` command end to end (TRUEAXIS_CLI_PATH): good runs
// reproduce the golden files, bad options exit 2 naming the option.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace trueaxis::exporter {
namespace {

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t a = 0;
  while (a <= text.size()) {
    const auto b = text.find('\n', a);
    out.push_back(text.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  return out;
}

namespace fs = std::filesystem;

const std::string kModel = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/export/golden/example_model.json";
const std::string kGolden = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/export/golden/";

struct Run {
  int code;
  std::string out;  // stdout + stderr
};

Run Cli(const std::string& args) {
  const std::string cmd = std::string(TRUEAXIS_CLI_PATH) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (p && fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int status = p ? pclose(p) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class ExportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trueaxis_export_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(ExportCli, LinuxCncMatchesTheGoldenFileAndReadsBack) {
  const auto r = Cli("export --model " + kModel + " --axis X --format linuxcnc --spacing 50 --temp nut=30 --temp bearing=26 --out " +
                     Path("x_comp.txt"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(ReadTextFile(Path("x_comp.txt")), ReadTextFile(kGolden + "x_comp_type1.txt"));
  EXPECT_NE(r.out.find("COMP_FILE_TYPE = 1"), std::string::npos) << r.out;
  // The INI lines say at which temperatures the thermal part was frozen (the file itself cannot).
  EXPECT_NE(r.out.find("# thermal state: coolant off, nut=30 bearing=26"), std::string::npos) << r.out;
  const auto back = Cli("export --read " + Path("x_comp.txt") + " --format linuxcnc --axis X");
  ASSERT_EQ(back.code, 0) << back.out;
  EXPECT_NE(back.out.find("400,-48.1000,-54.6000"), std::string::npos) << back.out;
}

TEST_F(ExportCli, EveryFormatWritesAndReadsBack) {
  const std::string base = "export --model " + kModel + " --axis X --spacing 20 --temp nut=30 --temp bearing=26 ";
  for (const auto& [format, file] : {std::pair<std::string, std::string>{"sinumerik", "X_EEC.INI"},
                                     {"fanuc", "x.tape"}, {"heidenhain", "X.CMA"}, {"csv", "x.csv"}}) {
    const auto w = Cli(base + "--format " + format + " --out " + Path(file));
    ASSERT_EQ(w.code, 0) << format << ": " << w.out;
    const auto r = Cli("export --read " + Path(file) + " --format " + format + " --axis X");
    ASSERT_EQ(r.code, 0) << format << ": " << r.out;
    EXPECT_NE(r.out.find("position_mm,forward_correction_um,reverse_correction_um"), std::string::npos) << r.out;
  }
  const auto note = Cli(base + "--format sinumerik --out " + Path("X2_EEC.INI"));
  EXPECT_NE(note.out.find("Siemens recommends 0 there"), std::string::npos) << note.out;
  const auto zeroed = Cli(base + "--format sinumerik --zero-at-reference --out " + Path("X3_EEC.INI"));
  EXPECT_EQ(zeroed.out.find("Siemens recommends 0 there"), std::string::npos) << zeroed.out;
  const auto frozen = Cli(base + "--format sinumerik --siemens-thermal-in-table --out " + Path("X4_EEC.INI"));
  ASSERT_EQ(frozen.code, 0) << frozen.out;
  EXPECT_NE(frozen.out.find("$MA_TEMP_COMP_TYPE[X1]=0"), std::string::npos) << frozen.out;
  EXPECT_NE(ReadTextFile(Path("X2_EEC.INI")).find("$MA_TEMP_COMP_TYPE[X1]=2"), std::string::npos);
  EXPECT_TRUE(fs::exists(Path("X_OFF.COM")));
  EXPECT_TRUE(fs::exists(Path("X_FLOOD.COM")));
  EXPECT_TRUE(fs::exists(Path("X_COLD.COM")));
}

TEST_F(ExportCli, MeasurementInput) {
  measure::Measurement m;
  m.SetMeta("axis", "Y");
  for (int run = 1; run <= 2; ++run)
    for (double x : {0.0, 100.0, 200.0}) {
      m.points.push_back({run, Direction::kForward, x, x / 20, {}, {}, 0});
      m.points.push_back({run, Direction::kReverse, x, x / 20 - 4, {}, {}, 0});
    }
  measure::WriteMeasurementCsv(m, Path("y.csv"));
  const auto w = Cli("export --measurement " + Path("y.csv") + " --format csv --out " + Path("y_table.csv"));
  ASSERT_EQ(w.code, 0) << w.out;
  const auto r = Cli("export --read " + Path("y_table.csv") + " --format csv");
  EXPECT_NE(r.out.find("200,-10.0000,-6.0000"), std::string::npos) << r.out;
  const auto t = Cli("export --measurement " + Path("y.csv") + " --format csv --temp nut=30 --out " + Path("z.csv"));
  EXPECT_EQ(t.code, 2);
  EXPECT_NE(t.out.find("'--temp'"), std::string::npos) << t.out;
}

TEST_F(ExportCli, BadOptionsExitTwoNamingTheOption) {
  const std::string m = "export --model " + kModel + " --axis X ";
  const std::string out = " --out " + Path("bad");
  const std::pair<std::string, std::string> cases[] = {
      {m + "--format linuxcnc --spacing 1" + out, "'--spacing'"},
      {m + "--format linuxcnc --count 300" + out, "'--count'"},
      {"export --model " + kModel + " --axis Q --format csv" + out, "'--axis'"},
      {m + "--format sinumerik --mode bidirectional" + out, "'--mode'"},
      {m + "--format linuxcnc --sign error" + out, "'--sign'"},
      {m + "--format plc" + out, "'--format'"},
      {m + "--format csv --temp nut" + out, "'--temp'"},
      {m + "--format csv --temp spindle=30" + out, "'--temp'"},
      {m + "--format csv --temp nut=30" + out, "'--temp'"},  // bearing missing
      {m + "--format csv --coolant lava" + out, "'--coolant'"},
      {m + "--format csv --range 10" + out, "'--range'"},
      {m + "--format csv --range -100:400" + out, "'--range'"},
      {m + "--format csv --measurement x.csv" + out, "'--model'"},
      {m + "--format heidenhain --out " + Path("X.txt"), "'--out'"},
      {m + "--format heidenhain --max-points 300" + out, "'--max-points'"},
      {m + "--format fanuc --detection-unit-um 0.3" + out, "'--spacing'"},
      {m + "--format fanuc --fanuc-magnification 1 --fanuc-point-limit 1 --spacing 50" + out, "'--fanuc-magnification'"},
      {m + "--format linuxcnc --comp-file-type 2" + out, "'--comp-file-type'"},
      {m + "--format heidenhain --temp nut=30 --temp bearing=26 --coolant mist --out " + Path("X.CMA"), "'--coolant'"},
      {"export --model " + Path("missing.json") + " --axis X --format csv" + out, "missing.json"},
  };
  for (const auto& [args, needle] : cases) {
    const auto r = Cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(needle), std::string::npos) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(Path("bad")));
}

TEST_F(ExportCli, FanucDerivedGridFitsThePointNumbersOfBothDirections) {
  // 41 numbers (0…40) for two directions: at most 20 points per direction → 50 mm.
  const auto r = Cli("export --model " + kModel + " --axis X --format fanuc --fanuc-max-point 40 --fanuc-axes 1 --out " +
                     Path("f.tape"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("step 50 mm"), std::string::npos) << r.out;
  EXPECT_NE(ReadTextFile(Path("f.tape")).find("N03624A1P50000"), std::string::npos);
}

// Tapes written with the defaults for two axes must not share point numbers: loading both would
// overwrite the first axis's data (X used 0…841 and Y started at 0 too).
TEST_F(ExportCli, FanucDefaultTapesOfTwoAxesUseDisjointPointNumbers) {
  auto range = [&](const std::string& tape_path) {
    int lo = 1 << 30, hi = -1;
    for (const auto& line : SplitLines(ReadTextFile(tape_path)))
      if (line.rfind("N1", 0) == 0 && line.size() > 6) {
        const int n = std::stoi(line.substr(2, 4));
        lo = std::min(lo, n), hi = std::max(hi, n);
      }
    return std::make_pair(lo, hi);
  };
  const auto x = Cli("export --model " + kModel + " --axis X --format fanuc --out " + Path("x.tape"));
  ASSERT_EQ(x.code, 0) << x.out;
  const auto y = Cli("export --model " + kModel + " --axis X --fanuc-axis 2 --format fanuc --out " + Path("y.tape"));
  ASSERT_EQ(y.code, 0) << y.out;
  const auto rx = range(Path("x.tape")), ry = range(Path("y.tape"));
  ASSERT_GE(rx.second, rx.first);
  ASSERT_GE(ry.second, ry.first);
  EXPECT_TRUE(rx.second < ry.first || ry.second < rx.first)
      << "A1 " << rx.first << "…" << rx.second << " overlaps A2 " << ry.first << "…" << ry.second;
}

// A data-driven thermal model (issue 15): fitted by `trueaxis thermal fit` on a synthetic series
// whose error is 2 µm/°C on a and 0.5 µm/°C on b (+0.3 µm), exported to every format at frozen
// temperatures and read back: every point holds the correction −error the data imply.
class ExportThermalCli : public ExportCli {
 protected:
  void SetUp() override {
    ExportCli::SetUp();
    std::string csv = "time_s,t_a_c,t_b_c,e_x_um\n";
    for (int r = 0; r < 200; ++r) {
      const double a = 20 + 8 * (1 - std::exp(-r / 50.0)), b = 21 + 0.7 * std::sin(r / 17.0);
      csv += fmt::format("{},{:.6f},{:.6f},{:.6f}\n", r * 30, a, b, 2 * (a - 20) + 0.5 * (b - 21) + 0.3);
    }
    WriteTextFile(Path("series.csv"), csv);
    const auto fit = Cli("thermal fit --series " + Path("series.csv") + " --model mlr --sensors-list a,b -o " + Path("m.json"));
    ASSERT_EQ(fit.code, 0) << fit.out;
    base_ = "export --thermal-model " + Path("m.json") + " --channel x --axis X --range 0:400 --spacing 50 ";
  }
  // The data rows of `export --read` output: position, forward and reverse correction.
  static std::vector<std::array<double, 3>> Rows(const std::string& printed) {
    std::vector<std::array<double, 3>> rows;
    for (const auto& line : SplitLines(printed)) {
      std::array<double, 3> v;
      if (!line.empty() && line[0] != '#' && std::sscanf(line.c_str(), "%lf,%lf,%lf", &v[0], &v[1], &v[2]) == 3)
        rows.push_back(v);
    }
    return rows;
  }
  // Every row's forward and reverse equal `correction_um` (the read-back prints 4 decimals).
  static std::size_t ExpectEveryPoint(const std::string& printed, double correction_um) {
    const auto rows = Rows(printed);
    for (const auto& [x, f, r] : rows) {
      EXPECT_NEAR(f, correction_um, 1e-3) << x;
      EXPECT_NEAR(r, correction_um, 1e-3) << x;
    }
    return rows.size();
  }
  std::string base_;
};

TEST_F(ExportThermalCli, EveryFormatHoldsMinusThePredictedErrorAndReadsBack) {
  for (const auto& [temps, correction] : {std::pair<std::string, double>{"--temp a=30 --temp b=22", -20.8},
                                          {"--temp a=25,b=20", -9.8}}) {
    for (const auto& [format, file] : {std::pair<std::string, std::string>{"linuxcnc", "x.txt"}, {"sinumerik", "X_EEC.INI"},
                                       {"heidenhain", "X.CMA"}, {"csv", "x.csv"}}) {
      const auto w = Cli(base_ + temps + " --format " + format + " --out " + Path(file));
      ASSERT_EQ(w.code, 0) << format << ": " << w.out;
      if (format == "linuxcnc")  // the INI lines name the temperatures the model was frozen at
        EXPECT_NE(w.out.find(temps.find("30") != std::string::npos ? "# thermal state: frozen at a=30 b=22"
                                                                  : "# thermal state: frozen at a=25 b=20"),
                  std::string::npos)
            << w.out;
      EXPECT_NE(w.out.find("the table is one offset"), std::string::npos) << w.out;
      const auto r = Cli("export --read " + Path(file) + " --format " + format + " --axis X");
      ASSERT_EQ(r.code, 0) << format << ": " << r.out;
      EXPECT_EQ(ExpectEveryPoint(r.out, correction), 9u) << format << " " << temps << ":\n" << r.out;
    }
  }
  // FANUC tables are zero at the reference: a position-independent offset vanishes, and is said to.
  const auto f = Cli(base_ + "--temp a=30,b=22 --format fanuc --out " + Path("x.tape"));
  ASSERT_EQ(f.code, 0) << f.out;
  EXPECT_NE(f.out.find("warning: the model predicts the same error at every position"), std::string::npos) << f.out;
  const auto r = Cli("export --read " + Path("x.tape") + " --format fanuc --axis X");
  EXPECT_GE(ExpectEveryPoint(r.out, 0.0), 9u) << r.out;
}

TEST_F(ExportThermalCli, BadOptionsExitTwoNamingTheOptionAndTheSensor) {
  const std::string out = " --format csv --out " + Path("bad.csv");
  const std::pair<std::string, std::vector<std::string>> cases[] = {
      {base_ + "--temp a=30" + out, {"'--temp'", "missing sensor 'b'", "(a, b)"}},
      {base_ + "--temp a=30,b=22,c=21" + out, {"'--temp'", "unknown sensor 'c'", "reads a, b"}},
      {"export --thermal-model " + Path("m.json") + " --channel x --axis X --temp a=30,b=22" + out, {"'--range'"}},
      {"export --thermal-model " + Path("m.json") + " --channel y_um --axis X --range 0:400 --temp a=30,b=22" + out,
       {"'channel'", "'y_um'", "it has: x"}},
      {"export --thermal-model " + Path("m.json") + " --axis X --range 0:400 --temp a=30,b=22" + out, {"'--channel'", "it has: x"}},
      {base_ + "--temp a=30,b=22 --model " + kModel + out, {"'--thermal-model'", "not both"}},
      {"export --model " + kModel + " --axis X --channel x" + out, {"'--channel'"}},
      {base_ + "--temp a=30,b=22 --coolant flood" + out, {"'--coolant'"}},
      {base_ + "--temp a=30,b=999" + out, {"'--temp'", "150"}},
  };
  for (const auto& [args, needles] : cases) {
    const auto r = Cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    for (const auto& needle : needles) EXPECT_NE(r.out.find(needle), std::string::npos) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(Path("bad.csv")));
}

// A PSO-BP network that takes the position (seed 003): the table follows the position with the
// correction's sign (error 0.01 µm/mm·(a − 20 °C), so the correction falls along the axis), and a
// range beyond the positions it was trained on (0…399 mm) is refused.
TEST_F(ExportThermalCli, PositionNetworkFollowsThePositionWithinItsTrainingRange) {
  std::string csv = "time_s,position_mm,t_a_c,e_x_um\n";
  for (int r = 0; r < 300; ++r) {
    const double a = 20 + 8 * (1 - std::exp(-r / 60.0)), x = (r * 37) % 400;
    csv += fmt::format("{},{},{:.6f},{:.6f}\n", r * 30, x, a, 0.01 * x * (a - 20));
  }
  WriteTextFile(Path("p.csv"), csv);
  ASSERT_EQ(Cli("thermal fit --series " + Path("p.csv") + " --model pso-bp -o " + Path("p.json")).code, 0);
  const std::string p = "export --thermal-model " + Path("p.json") + " --channel x --axis X --temp a=28 --format csv ";
  const auto w = Cli(p + "--range 0:350 --spacing 50 --out " + Path("p_table.csv"));
  ASSERT_EQ(w.code, 0) << w.out;
  const auto back = Cli("export --read " + Path("p_table.csv") + " --format csv");
  std::vector<double> fwd;
  for (const auto& [x, f, r] : Rows(back.out)) {
    EXPECT_NEAR(f, -0.01 * x * 8, 4.0) << x;  // the network's fit is within a few µm of the truth
    fwd.push_back(f);
  }
  ASSERT_EQ(fwd.size(), 8u) << back.out;
  EXPECT_LT(fwd.back(), fwd.front() - 20) << back.out;
  const auto beyond = Cli(p + "--range 0:500 --spacing 50 --out " + Path("beyond.csv"));
  EXPECT_EQ(beyond.code, 2) << beyond.out;
  EXPECT_NE(beyond.out.find("'--range'"), std::string::npos) << beyond.out;
}

TEST_F(ExportCli, CorruptTableOnReadNamesTheLine) {
  WriteTextFile(Path("c.txt"), "0 0 0\n10 0.001\n");
  const auto r = Cli("export --read " + Path("c.txt") + " --format linuxcnc");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("c.txt:2: field 'triplet'"), std::string::npos) << r.out;
}

TEST_F(ExportCli, RefusesAnOutputThatIsAnInput) {
  fs::copy_file(kModel, Path("m.json"));
  const std::string model = ReadTextFile(Path("m.json"));
  const auto r = Cli("export --model " + Path("m.json") + " --axis X --format csv --temp nut=30 --temp bearing=26 --out " +
                     Path("m.json"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("command line: field '--out': '" + Path("m.json") + "' is the input file"), std::string::npos) << r.out;
  EXPECT_EQ(ReadTextFile(Path("m.json")), model);
}

// A table read back must be one a controller can take: the readers refused nothing but syntax
// (a FANUC P99999 read as a 100 mm correction, a LinuxCNC file in µm, "# sign: sideways", one point).
TEST_F(ExportCli, ReadRefusesImplausibleTablesNamingFileLineAndField) {
  const std::string csv_head = "# axis: X\n# sign: correction\nposition_mm,forward_correction_um,reverse_correction_um\n";
  WriteTextFile(Path("huge.csv"), csv_head + "0,1,1\n50,1e308,2\n100,3,3\n");
  WriteTextFile(Path("sideways.csv"), "# sign: sideways\n" + csv_head.substr(csv_head.find("position_mm")) + "0,1,1\n50,2,2\n");
  WriteTextFile(Path("other_axis.csv"), "# axis: Y\nposition_mm,forward_correction_um,reverse_correction_um\n0,1,1\n50,2,2\n");
  WriteTextFile(Path("one.lin"), "0 0.001 0.002\n");
  WriteTextFile(Path("um.lin"), "0 0 0\n100 119.07 118.5\n200 3 3\n");  // µm where LinuxCNC wants mm
  const std::pair<std::string, std::string> cases[] = {
      {"--read " + Path("huge.csv") + " --format csv --axis X", "huge.csv:5: field 'forward_um'"},
      {"--read " + Path("sideways.csv") + " --format csv", "sideways.csv:1: field 'sign'"},
      {"--read " + Path("other_axis.csv") + " --format csv --axis X", "other_axis.csv: field 'axis': the table is for axis Y"},
      {"--read " + Path("one.lin") + " --format linuxcnc", "one.lin:1: field 'position_mm'"},
      {"--read " + Path("um.lin") + " --format linuxcnc", "um.lin:2: field 'forward_um'"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = Cli("export " + args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
  }
  // A FANUC tape with one pitch point edited to P99999 (99.999 mm at 1 µm units).
  const std::string base = "export --model " + kModel + " --axis X --spacing 20 --temp nut=30 --temp bearing=26 ";
  ASSERT_EQ(Cli(base + "--format fanuc --out " + Path("x.tape")).code, 0);
  std::string tape = ReadTextFile(Path("x.tape"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(tape, m, std::regex(R"(\nN1\d{4}P(-?\d+)\n)")));
  const std::size_t at = static_cast<std::size_t>(m.position(1));
  const int line = static_cast<int>(std::count(tape.begin(), tape.begin() + static_cast<long>(at), '\n')) + 1;
  tape.replace(at, static_cast<std::size_t>(m.length(1)), "99999");
  WriteTextFile(Path("huge.tape"), tape);
  auto r = Cli("export --read " + Path("huge.tape") + " --format fanuc");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(fmt::format("huge.tape:{}: field", line)), std::string::npos) << r.out;
  // The tables the writers make still read back (EveryFormatWritesAndReadsBack covers each format).
  r = Cli("export --read " + Path("x.tape") + " --format fanuc");
  EXPECT_EQ(r.code, 0) << r.out;
}

// Index 999999 among the right number of values: "MIN/MAX/STEP give 1201 points but the file holds 1201
// values", no line. Now the index is named at its line.
TEST_F(ExportCli, SinumerikIndexOutOfRangeIsNamedAtItsLine) {
  const std::string base = "export --model " + kModel + " --axis X --spacing 20 --temp nut=30 --temp bearing=26 ";
  ASSERT_EQ(Cli(base + "--format sinumerik --out " + Path("X_EEC.INI")).code, 0);
  std::string text = ReadTextFile(Path("X_EEC.INI"));
  const std::size_t at = text.find("$AA_ENC_COMP[0,3,");
  ASSERT_NE(at, std::string::npos) << text;
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  text.replace(at, std::string("$AA_ENC_COMP[0,3,").size(), "$AA_ENC_COMP[0,999999,");
  WriteTextFile(Path("IDX_EEC.INI"), text);
  const auto r = Cli("export --read " + Path("IDX_EEC.INI") + " --format sinumerik");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(fmt::format("IDX_EEC.INI:{}: field '$AA_ENC_COMP': point index 999999 is outside", line)),
            std::string::npos)
      << r.out;
}

// Given as nan, 0 or negative, these options read as "not given" and silently took the default.
TEST_F(ExportCli, OptionsThatWouldReadAsTheDefaultAreRefused) {
  const std::string m = "export --model " + kModel + " --axis X --temp nut=30 --temp bearing=26 ";
  const std::string out = " --out " + Path("bad");
  const std::pair<std::string, std::string> cases[] = {
      {m + "--format csv --spacing nan" + out, "field '--spacing'"},
      {m + "--format csv --start nan" + out, "field '--start'"},
      {m + "--format csv --reference-mm nan" + out, "field '--reference-mm'"},
      {m + "--format csv --count 0" + out, "field '--count'"},
      {m + "--format csv --max-points 0" + out, "field '--max-points'"},
      {m + "--format csv --max-points -1" + out, "field '--max-points'"},
      {m + "--format fanuc --max-feed -1" + out, "field '--max-feed'"},
      {m + "--format fanuc --max-feed nan" + out, "field '--max-feed'"},
      {m + "--format fanuc --max-feed 0" + out, "field '--max-feed'"},
      {m + "--format csv --range nan:10" + out, "field '--range'"},
      {m + "--format csv --range 0:1e9" + out, "field '--range'"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = Cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(Path("bad"))) << args;
  }
}

}  // namespace
}  // namespace trueaxis::exporter
