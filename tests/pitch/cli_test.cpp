// The pitch commands end to end: calibrate, write the error file, run with
// feed-forward, report, export; bad input exits 2 naming file, line and field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
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
  r = RunCli("sim fine --machine " + kMachine + " --axis Z --runs 2 --pitch-file " + table + " --out " + after);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("table applied (ahead feed-forward"), std::string::npos) << r.output;
  r = RunCli("pitch report --before " + before + " --after " + after + " --pitch-file " + table + " --out " + html);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(html));
  r = RunCli("export --pitch-file " + table + " --format linuxcnc --out " + (d / "z_comp.txt").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
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

TEST(PitchCli, ACoarseRunIsRefusedForAOncePerLeadTable) {
  const std::string run = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_cold.csv";
  const auto r = RunCli("pitch table --measurement " + run + " --lead-mm 10 --out /dev/null");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("field 'target_mm': targets up to"), std::string::npos) << r.output;
}

}  // namespace
