// The pitch commands end to end: calibrate, write the error file, run with
// feed-forward, report, export; bad input exits 2 naming file, line and field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli_runner.hpp"
#include "support/read_text.hpp"

namespace {

namespace fs = std::filesystem;
using trueaxis::testing::ReadText;
using trueaxis::testing::RunCli;

const std::string kMachine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc400_small.toml";

fs::path Scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("trueaxis_pitch_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(PitchCli, TableRefusesAnOutputThatIsItsMeasurement) {
  const fs::path d = Scratch("over");
  const std::string run = (d / "fine.csv").string();
  fs::copy_file(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_cold.csv", run);
  const auto size = fs::file_size(run);
  const auto r = RunCli("pitch table --measurement " + run + " --out " + run);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("command line: field '--out': '" + run + "' is the input file"), std::string::npos) << r.output;
  EXPECT_EQ(fs::file_size(run), size);
  fs::remove_all(d);
}

TEST(PitchCli, CalibrateTableRunReportExport) {
  const fs::path d = Scratch("flow");
  const std::string before = (d / "Z_fine.csv").string(), table = (d / "Z.pitch.csv").string(),
                    after = (d / "Z_on.csv").string(), html = (d / "r.html").string();
  auto r = RunCli("sim fine --machine " + kMachine + " --axis Z --runs 2 --out " + before);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // A given --reference-mm that is no position is refused, not read as "not given".
  r = RunCli("pitch table --measurement " + before + " --reference-mm nan --out " + table);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--reference-mm'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(table));
  // Samples per lead: auto or a whole number 1…64, anything else refused before a file is written.
  for (const char* bad : {"abc", "0", "65", "2x", "-1"}) {
    r = RunCli("pitch table --measurement " + before + " --samples-per-lead " + bad + " --out " + table);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("field '--samples-per-lead'"), std::string::npos) << bad << "\n" << r.output;
    EXPECT_FALSE(fs::exists(table)) << bad;
  }
  r = RunCli("pitch table --measurement " + before + " --out " + table);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("periodic: h1 (5 mm)"), std::string::npos) << r.output;  // resolved at lead/4
  EXPECT_NE(r.output.find("table: "), std::string::npos) << r.output;              // the automatic choice, said
  EXPECT_NE(r.output.find(" per lead: the fewest whose table meets"), std::string::npos) << r.output;
  // The calibration covered the whole 300 mm travel: the table says so, and its replay stays inside it.
  EXPECT_NE(ReadText(table).find("# measured_from_mm: 0.25\n# measured_to_mm: 299.75\n"), std::string::npos);
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  r = RunCli("sim fine --machine " + kMachine + " --axis Z --runs 2 --pitch-file " + table + " --out " + after);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("table applied (ahead feed-forward"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning: the axis moved beyond"), std::string::npos) << r.output;
  r = RunCli("pitch report --before " + before + " --after " + after + " --pitch-file " + table + " --out " + html);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(html));
  r = RunCli("export --pitch-file " + table + " --format linuxcnc --out " + (d / "z_comp.txt").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The range as a comment: in the INI snippet (a LinuxCNC COMP file holds none), in the CSV table.
  const std::string range_note = "measured range (vouched for): 0.25…299.75 mm; beyond it the end values are held";
  EXPECT_NE(r.output.find("# " + range_note), std::string::npos) << r.output;
  r = RunCli("export --pitch-file " + table + " --format csv --out " + (d / "z.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(ReadText(d / "z.csv").find("# provenance: " + range_note), std::string::npos);
  // The table is for Z: running it on X is refused.
  r = RunCli("sim fine --machine " + kMachine + " --axis X --runs 2 --pitch-file " + table + " --out " + after);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field 'axis': the file is for axis Z"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(PitchCli, BadErrorFileExitsTwoWithFileLineField) {
  const fs::path d = Scratch("bad");
  const std::string bad = (d / "bad.pitch.csv").string();
  std::ofstream(bad) << "# axis: X\n# lead_mm: 5\nposition_mm,error_up_um,error_down_um\n5,1,2\n10,x,2\n";
  auto r = RunCli("export --pitch-file " + bad + " --format csv --out " + (d / "o.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(bad + ":5: field 'error_up_um': 'x' is not a number"), std::string::npos) << r.output;
  r = RunCli("sim fine --machine " + kMachine + " --axis X --pitch-file " + bad + " --out " + (d / "o.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(":5: field 'error_up_um'"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(PitchCli, ALongTableIsRefusedForLinuxCncAndResampledOnRequest) {
  const fs::path d = Scratch("long");
  const std::string f = (d / "long.pitch.csv").string();
  {
    std::ofstream out(f);
    out << "# axis: X\n# lead_mm: 5\n# reference_mm: 0\nposition_mm,error_up_um,error_down_um\n";
    for (int i = 1; i <= 300; ++i) out << 5 * i << "," << (i % 2) << "," << (i % 2) - 4 << "\n";
  }
  auto r = RunCli("export --pitch-file " + f + " --format linuxcnc --out " + (d / "c.txt").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("300 samples (5 mm apart, lead 5 mm) exceed the format's limit of 256 points; nothing is truncated"),
            std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "c.txt"));
  r = RunCli("export --pitch-file " + f + " --format linuxcnc --spacing 10 --out " + (d / "c.txt").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("up to 1.000 um lost"), std::string::npos) << r.output;
  fs::remove_all(d);
}

// A calibration over part of the travel: `pitch table` says which part is missing, the table goes
// into the model `run` loads with the range it vouches for, and `predict` beyond it warns and holds.
// A pitch file without the range still loads, with a warning that the range is unknown.
TEST(PitchCli, APartialTableWarnsAndItsRangeGoesIntoTheModel) {
  const fs::path d = Scratch("range");
  const std::string fine = (d / "fine.csv").string(), table = (d / "X.pitch.csv").string(),
                    model = (d / "model.json").string(), out = (d / "model_pitch.json").string();
  auto r = RunCli("sim fine --machine " + kMachine + " --axis X --runs 2 --out " + fine);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCli("pitch table --measurement " + fine + " --travel-mm 450 --out " + table);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the run measured 0.25…399.75 mm of the travel 0…450 mm; the table vouches for nothing in "
                          "399.75…450 mm"),
            std::string::npos) << r.output;
  std::ofstream(model) << R"({"format": "trueaxis-model", "format_version": 1, "machine": "VMC-400", "revision": 1,
    "axes": [{"axis": "X", "reference_position_mm": 0, "key_sensors": [], "baseline_temp_c": [], "rho_um_per_mm_per_c": 0,
              "forward": {"geometric": {"kind": "polynomial", "center_mm": 200, "half_span_mm": 200, "coefficients_um": [0]}},
              "reverse": {"geometric": {"kind": "polynomial", "center_mm": 200, "half_span_mm": 200, "coefficients_um": [0]}}}]})";
  r = RunCli("pitch into-model --pitch-file " + table + " --model " + model + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("axis X: geometric part = the pitch table"), std::string::npos) << r.output;
  EXPECT_NE(ReadText(out).find("\"measured_range_mm\": [\n        0.25,\n        399.75\n      ]"), std::string::npos)
      << ReadText(out);
  r = RunCli("predict --model " + out + " --axis X --position-mm 420 --direction + --geometric-only");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("420 mm is outside the measured range 0.25 … 399.75 mm (geometric part held at its end)"),
            std::string::npos) << r.output;
  // `run` against the virtual machine (every axis machining over 10–90 % = 40…360 mm) with a table
  // measured over 100…300 mm only: the alarm outside_measured_range on X, visible on stderr.
  {
    std::ifstream in(fine);
    std::ofstream part(d / "part.csv");
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') {
        part << line << "\n";
        continue;
      }
      if (!header) {  // target_mm is the third column
        header = true;
        ASSERT_EQ(line.substr(0, 23), "run,direction,target_mm") << line;
        part << line << "\n";
        continue;
      }
      const double x = std::stod(line.substr(line.find(',', line.find(',') + 1) + 1));
      if (x >= 100 && x <= 300) part << line << "\n";
    }
  }
  r = RunCli("pitch table --measurement " + (d / "part.csv").string() + " --out " + (d / "part.pitch.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the table vouches for nothing in 0…100 mm and 300…400 mm"), std::string::npos) << r.output;
  const std::string part_model = (d / "model_part.json").string();
  r = RunCli("pitch into-model --pitch-file " + (d / "part.pitch.csv").string() + " --model " + model + " --out " + part_model);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ofstream(d / "run.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                << "\"\nseed = 1\ntime_scale = 60\nreciprocate = true\nfeed_mm_min = 3000\nduty = 0.7\n"
                                   "[model]\nfile = \"" << part_model
                                << "\"\n[loop]\nperiod_s = 0.01\nduration_s = 2\n[[axis]]\nname = \"X\"\n";
  r = RunCli("run --config " + (d / "run.toml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("outside_measured_range(X)"), std::string::npos) << r.output;
  // The same file without the range (as files written before it): loads, said unknown.
  std::string text = ReadText(table);
  const auto at = text.find("# measured_from_mm");
  text.erase(at, text.find("position_mm,") - at);
  const std::string old_table = (d / "old.pitch.csv").string();
  std::ofstream(old_table) << text;
  r = RunCli("export --pitch-file " + old_table + " --format csv --out " + (d / "o.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the file does not say which range axis X was measured over"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(PitchCli, ACoarseRunIsRefusedForAOncePerLeadTable) {
  const std::string run = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_cold.csv";
  const auto r = RunCli("pitch table --measurement " + run + " --lead-mm 10 --out /dev/null");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("field 'target_mm': targets up to"), std::string::npos) << r.output;
}

}  // namespace
