// Programs and machine files: what is accepted, and bad input refused with file, line and word.
#include <cmath>

#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/fiveaxis/program.hpp"

namespace trueaxis::fiveaxis {
namespace {

FiveAxisMachine TableAC() {
  return ParseFiveAxisMachineToml("[machine]\nfamily = \"table_ac\"\n[kinematics]\ntilt_min_deg = -30\ntilt_max_deg = 100\n",
                                  "m.toml");
}

// Expects an InputError at `line` whose field contains `field`.
template <typename F>
void ExpectError(F f, int line, const std::string& field) {
  try {
    f();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(e.field().find(field), std::string::npos) << e.what();
  }
}

TEST(FiveAxisProgram, ReadsTheSubset) {
  const auto m = TableAC();
  const ToolPath p = ParseGcodeProgram(
      "%\n(comment)\nG21 G90\nG0 X1 Y2 Z3 A0 C0\nG1 X10 F600 ; feed\nG91 G1 Y5 C90\nG20 G1 X1\nG90 G21 G1 A45\nM30\n%\n",
      "p.nc", m);
  ASSERT_EQ(p.vertices.size(), 5u);
  EXPECT_EQ(p.vertices[0].move, MoveKind::kStart);  // the first G0 positions the machine
  EXPECT_DOUBLE_EQ(p.vertices[0].tip_mm.x(), 1);
  EXPECT_DOUBLE_EQ(p.vertices[1].tip_mm.x(), 10);
  EXPECT_DOUBLE_EQ(p.vertices[1].feed_mm_per_min, 600);
  EXPECT_DOUBLE_EQ(p.vertices[2].tip_mm.y(), 7);     // incremental
  EXPECT_DOUBLE_EQ(p.vertices[2].rot_deg, 90);
  EXPECT_DOUBLE_EQ(p.vertices[3].tip_mm.x(), 10 + 25.4);  // G20: inch, still incremental
  EXPECT_DOUBLE_EQ(p.vertices[3].feed_mm_per_min, 600);
  EXPECT_DOUBLE_EQ(p.vertices[4].tilt_deg, 45);
  EXPECT_EQ(p.vertices[4].source_line, 8);
}

TEST(FiveAxisProgram, RefusesBadProgramsWithTheLine) {
  const auto m = TableAC();
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 F100\nG2 X1 Y1 I1\n", "p.nc", m); }, 3, "G2");
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 Q3 F100\n", "p.nc", m); }, 2, "Q3");
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 B10 F100\n", "p.nc", m); }, 2, "B10");  // no B on an A/C table
  ExpectError([&] { ParseGcodeProgram("G0 X0\n\nG1 X5\n", "p.nc", m); }, 3, "F");           // missing feed
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 A120 F100\n", "p.nc", m); }, 2, "A");   // beyond tilt_max_deg
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 A-31 F100\n", "p.nc", m); }, 2, "A");
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5.2.1 F100\n", "p.nc", m); }, 2, "X");
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG93 G1 X5\n", "p.nc", m); }, 2, "F");       // inverse time: F per block
  ExpectError([&] { ParseGcodeProgram("G0 X0 (open comment\n", "p.nc", m); }, 1, "(");
  ExpectError([&] { ParseGcodeProgram("G1 X0 F100\nG1 X1 X2\n", "p.nc", m); }, 2, "X");
}

TEST(FiveAxisProgram, CsvWithToolAxisOrAngles) {
  const auto m = TableAC();
  const ToolPath p = ParseCsvProgram("x_mm,y_mm,z_mm,i,j,k,feed_mm_per_min\n0,0,0,0,0,1,1000\n10,0,0,0,-0.5,0.866025403784,1000\n",
                                     "p.csv", m, 0);
  ASSERT_EQ(p.vertices.size(), 2u);
  EXPECT_NEAR(p.vertices[1].tilt_deg, 30, 1e-6);  // axis tilted towards −Y: A = +30 at C = 0
  EXPECT_NEAR(p.vertices[1].rot_deg, 0, 1e-6);
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg\n0,0,0,0,0\n1,0,0,0,0\n", "p.csv", m, 0); }, 3,
              "feed_mm_per_min");
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg\n0,0,0,0,0\n1,0,0,101,0\n", "p.csv", m, 500); }, 3, "A");
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,b_deg,c_deg\n0,0,0,0,0\n", "p.csv", m, 500); }, 1, "b_deg");
}

TEST(FiveAxisProgram, RefusesNonFiniteAndAbsurdFeeds) {
  const auto m = TableAC();
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X5 F2000000000\n", "p.nc", m); }, 2, "F2");  // µm/min?
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg,feed_mm_per_min\n0,0,0,0,0,1\n1,0,0,0,0,0\n", "p.csv", m, 0); },
              3, "feed_mm_per_min");
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg\n0,0,0,0,0\n1,0,0,0,0\n", "p.csv", m, std::nan("")); }, 0,
              "--feed");
  // Slow is not absurd: 0.1 mm/min reads (the interpolator bounds the work).
  EXPECT_NO_THROW(ParseGcodeProgram("G0 X0\nG1 X5 F0.1\n", "p.nc", m));
}

TEST(FiveAxisProgram, RefusesLinearPositionsOutsideTheTravel) {
  const auto m = ParseFiveAxisMachineToml(
      "[machine]\nfamily = \"table_ac\"\n[kinematics]\nx_min_mm = -400\nx_max_mm = 400\n", "m.toml");
  EXPECT_NO_THROW(ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg\n0,0,0,0,0\n390,0,0,0,0\n", "p.csv", m, 500));
  ExpectError([&] { ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg\n0,0,0,0,0\n100000,0,0,0,0\n", "p.csv", m, 500); }, 3,
              "X");
  ExpectError([&] { ParseGcodeProgram("G0 X0\nG1 X10 F100\nG1 X-401\n", "p.nc", m); }, 3, "X");
  // The travel is of the joints: C = 90 turns program X into machine Y, which has no limit here.
  EXPECT_NO_THROW(ParseGcodeProgram("G0 X0\nG1 X10 F100\nG1 C90\nG1 X-401\n", "p.nc", m));
  ExpectError([] { ParseFiveAxisMachineToml("[machine]\nfamily = \"table_ac\"\n[kinematics]\nz_min_mm = 5\nz_max_mm = 5\n", "m.toml"); },
              5, "z_max_mm");
}

TEST(FiveAxisProgram, WrittenProgramReadsBackTheSame) {
  const auto m = TableAC();
  const Kinematics kin(m.kinematics);
  ToolPath path = MakeTestPath("inclined-circle", kin, 2000);
  path.vertices.resize(50);
  for (std::size_t i = 1; i < path.vertices.size(); ++i) {  // as a corrected program: inverse time
    path.vertices[i].move = MoveKind::kInverseTime;
    path.vertices[i].duration_s = 0.0005;
  }
  for (const bool csv : {false, true}) {
    const ToolPath back = csv ? ParseCsvProgram(WriteCsvProgram(path, m), "p.csv", m, 0)
                              : ParseGcodeProgram(WriteGcodeProgram(path, m, "round trip"), "p.nc", m);
    ASSERT_EQ(back.vertices.size(), path.vertices.size());
    for (std::size_t i = 0; i < path.vertices.size(); ++i) {
      EXPECT_LT((back.vertices[i].tip_mm - path.vertices[i].tip_mm).norm(), 2e-6);
      EXPECT_NEAR(back.vertices[i].tilt_deg, path.vertices[i].tilt_deg, 1e-6);
      EXPECT_EQ(back.vertices[i].move, path.vertices[i].move);
      EXPECT_NEAR(back.vertices[i].duration_s, path.vertices[i].duration_s, 1e-12);
    }
  }
}

TEST(FiveAxisMachineFile, RefusesUnknownKeysAndBadValuesWithTheLine) {
  ExpectError([] { ParseFiveAxisMachineToml("[machine]\nfamily = \"table_ac\"\n\n[drive.X]\nkp_per_s = 40\nlead = 10\n", "m.toml"); },
              6, "drive.X.lead");
  ExpectError([] { ParseFiveAxisMachineToml("[machine]\nfamily = \"table_xy\"\n", "m.toml"); }, 2, "machine.family");
  ExpectError([] { ParseFiveAxisMachineToml("[machine]\nfamily = \"head_bc\"\nservo_rate_hz = 8000\n", "m.toml"); }, 3,
              "machine.servo_rate_hz");
  ExpectError([] { ParseFiveAxisMachineToml("[machine]\nfamily = \"head_bc\"\n[drive.A]\nkp_per_s = 40\n", "m.toml"); }, 3,
              "drive.A");  // a B/C head has no A drive
  const auto m = ParseFiveAxisMachineToml("[machine]\nfamily = \"head_bc\"\n[drive.B]\ngear_ratio = 50\n", "m.toml");
  EXPECT_TRUE(m.drives[kTilt].rotary);
  EXPECT_DOUBLE_EQ(m.drives[kTilt].transmission, 50);
}

TEST(FiveAxisCli, BadProgramExitsWithCode2AndTheLine) {
  const std::string bad = ::testing::TempDir() + "bad_program.nc";
  FILE* f = fopen(bad.c_str(), "w");
  fputs("G0 X0 Y0 Z0\nG1 X10 F500\nG1 X20 W3\n", f);
  fclose(f);
  const auto r = trueaxis::testing::RunCli("fiveaxis simulate --machine " + std::string(TRUEAXIS_SOURCE_DIR) +
                                           "/examples/fiveaxis/table_ac.toml --program " + bad);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad_program.nc:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("W3"), std::string::npos) << r.output;
}

// --method chooses how the corrected command is found; anything else is refused.
TEST(FiveAxisCli, CorrectionMethodIsChosenOrRefused) {
  const std::string machine = " --machine " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/table_ac.toml";
  auto r = trueaxis::testing::RunCli("fiveaxis correct" + machine + " --path inclined-circle --feed 3000 --method newton");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--method"), std::string::npos) << r.output;
  r = trueaxis::testing::RunCli("fiveaxis correct" + machine + " --path inclined-circle --feed 3000 --method passes --iterations 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("FF + correction"), std::string::npos) << r.output;
}

// The sweep's A2: F0.001 exhausted memory (std::bad_alloc, exit 1); now a
// clean exit 2 naming the line, before anything large is allocated.
TEST(FiveAxisCli, SlowFeedIsRefusedWithTheLineInsteadOfExhaustingMemory) {
  const std::string slow = ::testing::TempDir() + "slow_feed.nc";
  FILE* f = fopen(slow.c_str(), "w");
  fputs("G1 X10 Y0 Z0 A0 C0 F4000\nG1 X100 F0.001\nM30\n", f);
  fclose(f);
  const std::string machine = " --machine " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/table_ac.toml";
  auto r = trueaxis::testing::RunCli("fiveaxis simulate" + machine + " --program " + slow);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("slow_feed.nc:2: field 'F'"), std::string::npos) << r.output;
  r = trueaxis::testing::RunCli("fiveaxis simulate" + machine + " --path cone --feed 0.00001");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--feed'"), std::string::npos) << r.output;
  for (const char* rest : {"-1", "nan", "11"}) {
    r = trueaxis::testing::RunCli("fiveaxis simulate" + machine + " --path cone --feed 3000 --end-rest-s " + rest);
    EXPECT_EQ(r.exit_code, 2) << rest << "\n" << r.output;
    EXPECT_NE(r.output.find("field '--end-rest-s'"), std::string::npos) << rest << "\n" << r.output;
  }
  r = trueaxis::testing::RunCli("fiveaxis simulate" + machine + " --path inclined-pocket --feed 3000 --kf 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("end point: "), std::string::npos) << r.output;
  r = trueaxis::testing::RunCli("fiveaxis simulate" + machine + " --path cone --feed nan");  // was a 4.3 µm answer, exit 0
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--feed': not a finite feed"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace trueaxis::fiveaxis
