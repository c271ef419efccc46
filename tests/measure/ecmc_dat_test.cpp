#include "trueaxis/measure/ecmc_dat.hpp"

#include <string>

#include <gtest/gtest.h>

#include "support/shared_data.hpp"

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/measure/measurement_file.hpp"

using namespace trueaxis;
using measure::ParseEcmcDat;

namespace {
const std::string kDir = std::string(TRUEAXIS_SHARED_DATA_DIR) + "/ecmc/";

// Expects ParseEcmcDat(text) to throw an InputError at `line` naming `field`.
void ExpectError(const std::string& text, int line, const std::string& field, const std::string& words = "") {
  try {
    ParseEcmcDat(text, "t.dat");
    FAIL() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "t.dat");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    if (!words.empty()) EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(EcmcDat, ReadsFatSatWithItsQuirks) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kDir + "fat_sat_test.dat");
  const auto m = measure::ReadEcmcDat(kDir + "fat_sat_test.dat");
  EXPECT_EQ(m.points.size(), 50u);
  EXPECT_EQ(m.Runs().size(), 5u);
  const auto t = m.Targets();
  ASSERT_EQ(t.size(), 5u);
  EXPECT_DOUBLE_EQ(t[0], -10);
  EXPECT_DOUBLE_EQ(t[2], 0.24);  // REF_DATA_FWD[3,1]=.2399139810 (no leading zero)
  EXPECT_EQ(m.Meta("unit"), "mm");
  EXPECT_EQ(m.Meta("cycles"), "5");
  EXPECT_EQ(m.Meta("format"), "ecmc dat");
  ASSERT_TRUE(m.Meta("description"));
  EXPECT_NE(m.Meta("description")->find("Input data file"), std::string::npos);  // from "TEST_DATA=# ..."
  // First reading: line 23, REF_DATA_FWD[1,1]=-10.0000990190, target -10.
  const auto& p = m.points.front();
  EXPECT_EQ(p.source_line, 23);
  EXPECT_EQ(p.run, 1);
  EXPECT_EQ(p.direction, Direction::kForward);
  EXPECT_NEAR(p.deviation_um, -0.099019, 1e-9);
  // A backward reading, REF_DATA_BWD[3,1]=.2399279810 at target 0.24.
  bool found = false;
  for (const auto& q : m.points)
    if (q.direction == Direction::kReverse && q.run == 1 && std::abs(q.target_mm - 0.24) < 1e-9) {
      EXPECT_NEAR(q.deviation_um, -0.072019, 1e-9);
      found = true;
    }
  EXPECT_TRUE(found);
  EXPECT_NO_THROW(measure::ValidateForEvaluation(m));
}

TEST(EcmcDat, ReadsMcu1025) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kDir + "mcu1025_fat_sat.dat");
  const auto m = measure::ReadEcmcDat(kDir + "mcu1025_fat_sat.dat");
  EXPECT_EQ(m.points.size(), 50u);
  EXPECT_EQ(m.Targets().front(), 15);
  EXPECT_NEAR(m.points.front().deviation_um, 93.1842960383320, 1e-6);  // 15.0931842960383320 − 15
  EXPECT_NO_THROW(measure::ValidateForEvaluation(m));
}

TEST(EcmcDat, CrlfAndUnitsAndOrder) {
  const std::string body = "TGT_DATA[1]=1\nREF_DATA_BWD[1,2]=1.5\nREF_DATA_FWD[1,1]=1.25\nUNIT=um\n";
  auto m = ParseEcmcDat(body, "a.dat");
  ASSERT_EQ(m.points.size(), 2u);
  EXPECT_DOUBLE_EQ(m.points[0].deviation_um, 0.5);   // in file order; UNIT may come last
  EXPECT_DOUBLE_EQ(m.points[1].deviation_um, 0.25);
  EXPECT_DOUBLE_EQ(m.points[0].target_mm, 0.001);
  std::string crlf;
  for (char c : body) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  auto m2 = ParseEcmcDat(crlf + "  \r\n", "b.dat");
  ASSERT_EQ(m2.points.size(), 2u);
  EXPECT_EQ(m2.points[1].deviation_um, m.points[1].deviation_um);
  auto m3 = ParseEcmcDat("UNIT=nm\nTGT_DATA[1]=100\nREF_DATA_FWD[1,1]=350\n", "c.dat");
  EXPECT_DOUBLE_EQ(m3.points[0].deviation_um, 0.25);
}

TEST(EcmcDat, BadInputsNameLineAndField) {
  // Errors after the last line point one past it, as in every trueaxis reader (core/text_lines.hpp).
  ExpectError("", 1, "TGT_DATA", "empty");
  ExpectError("# only comments\n", 2, "TGT_DATA");
  ExpectError("TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=abc\n", 2, "REF_DATA_FWD[1,1]", "not a finite number");
  ExpectError("TGT_DATA[1]=nan\n", 1, "TGT_DATA[1]");
  ExpectError("TGT_DATA[1]=0\nREF_DATA_FWD[1,0]=0\n", 2, "REF_DATA_FWD[1,0]", "index");
  ExpectError("TGT_DATA[1]=0\nREF_DATA_FWD[1]=0\n", 2, "REF_DATA_FWD[1]", "two indices");
  ExpectError("TGT_DATA[1,2]=0\n", 1, "TGT_DATA[1,2]", "one index");
  ExpectError("TGT_DATA[1=0\n", 1, "TGT_DATA[1", "unterminated");
  ExpectError("FOO_DATA[1]=0\n", 1, "FOO_DATA[1]", "unknown indexed variable");
  ExpectError("TGT_DATA[1]=0\nTGT_DATA[1]=1\n", 2, "TGT_DATA[1]", "twice");
  ExpectError("TGT_DATA[1]=0\nREF_DATA_FWD[2,1]=0\n", 2, "REF_DATA_FWD[2,1]", "no TGT_DATA[2]");
  ExpectError("TGT_DATA[1]=0\nTGT_DATA[2]=1\nREF_DATA_FWD[1,1]=0\n", 2, "TGT_DATA[2]", "no REF_DATA");
  ExpectError("UNIT=parsec\nTGT_DATA[1]=0\n", 1, "UNIT", "unknown unit");
  ExpectError("CYCLES=five\n", 1, "CYCLES");
  ExpectError("POSITIONS=2\nTGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0\n", 1, "POSITIONS", "declares 2 positions");
  ExpectError("CYCLES=2\nTGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0\n", 1, "CYCLES", "declares 2 cycles");
  ExpectError("CYCLES=1\nTGT_DATA[1]=0\nREF_DATA_FWD[1,2]=0\n", 3, "REF_DATA_FWD[1,2]", "beyond CYCLES");
  ExpectError("TGT_DATA[1]=0\njust some words\n", 2, "just some words", "KEY=VALUE");
  ExpectError("UNIT=mm\nUNIT=um\n", 2, "UNIT", "twice");
  ExpectError("BAD KEY=1\n", 1, "BAD KEY");
  ExpectError("REF_DATA_FWD[1,1]=0\n", 1, "TGT_DATA");
}

TEST(MeasurementFile, DetectsFormatByContentThenExtension) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kDir + "fat_sat_test.dat");
  using measure::DetectMeasurementFormat;
  using measure::MeasurementFormat;
  EXPECT_EQ(DetectMeasurementFormat("x.txt", "TEST_DATA=# hi\n"), MeasurementFormat::kEcmcDat);
  EXPECT_EQ(DetectMeasurementFormat("x.csv", "UNIT=mm\nTGT_DATA[1]=0\n"), MeasurementFormat::kEcmcDat);
  EXPECT_EQ(DetectMeasurementFormat("x.DAT", ""), MeasurementFormat::kEcmcDat);
  EXPECT_EQ(DetectMeasurementFormat("dir.dat/x", "run,direction"), MeasurementFormat::kCanonicalCsv);
  EXPECT_EQ(DetectMeasurementFormat("x.csv", "run,direction,target_mm,deviation_um\n"),
            MeasurementFormat::kCanonicalCsv);
  const auto m = measure::ReadMeasurementFile(kDir + "fat_sat_test.dat");
  EXPECT_EQ(m.points.size(), 50u);
}

TEST(EcmcDat, ConvertsLosslesslyToCanonicalCsv) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kDir + "mcu1025_fat_sat.dat");
  const auto m = measure::ReadEcmcDat(kDir + "mcu1025_fat_sat.dat");
  const auto back = measure::ParseMeasurementCsv(measure::FormatMeasurementCsv(m), "round.csv");
  ASSERT_EQ(back.points.size(), m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    EXPECT_EQ(back.points[i].deviation_um, m.points[i].deviation_um);
    EXPECT_EQ(back.points[i].target_mm, m.points[i].target_mm);
    EXPECT_EQ(back.points[i].direction, m.points[i].direction);
  }
  EXPECT_EQ(back.Meta("unit"), "mm");
}
