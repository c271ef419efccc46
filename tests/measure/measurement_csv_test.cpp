#include "trueaxis/measure/measurement_csv.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::measure {
namespace {

const char* kGood =
    "# axis: X\n"
    "# machine: VMC-850\n"
    "run,direction,target_mm,deviation_um,time_s,t_nut_c,t_air_c\n"
    "1,+,0,0.8,0,20.5,20.0\n"
    "1,+,25,1.25,10,20.5,20.0\n"
    "1,-,25,3.5,20,20.6,\n"
    "1,-,0,2.5,30,20.6,20.0\n"
    "2,+,0,0.9,40,20.7,20.1\n"
    "2,+,25,1.2,50,20.7,20.1\n"
    "2,-,25,3.4,60,20.7,20.1\n"
    "2,-,0,2.4,70,20.8,20.1\n";

std::string ErrorOf(const std::string& text) {
  try {
    auto m = ParseMeasurementCsv(text, "f.csv");
    ValidateForEvaluation(m);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MeasurementCsv, ReadsMetadataColumnsAndPoints) {
  auto m = ParseMeasurementCsv(kGood, "f.csv");
  EXPECT_EQ(m.Meta("axis").value(), "X");
  EXPECT_EQ(m.Meta("machine").value(), "VMC-850");
  ASSERT_EQ(m.sensor_names, (std::vector<std::string>{"nut", "air"}));
  ASSERT_EQ(m.points.size(), 8u);
  EXPECT_EQ(m.points[2].direction, Direction::kReverse);
  EXPECT_DOUBLE_EQ(m.points[1].deviation_um, 1.25);
  EXPECT_TRUE(std::isnan(m.points[2].temperatures_c[1]));
  EXPECT_EQ(m.points[2].source_line, 6);
  EXPECT_EQ(m.Targets(), (std::vector<double>{0, 25}));
  EXPECT_EQ(m.Runs(), (std::vector<int>{1, 2}));
  EXPECT_NO_THROW(ValidateForEvaluation(m));
}

TEST(MeasurementCsv, RoundTripIsLossless) {
  auto m = ParseMeasurementCsv(kGood, "f.csv");
  m.points[0].deviation_um = 0.1 + 0.2;  // not exactly representable in short decimal
  m.points[3].target_mm = 1.0 / 3.0;
  auto again = ParseMeasurementCsv(FormatMeasurementCsv(m), "g.csv");
  ASSERT_EQ(again.points.size(), m.points.size());
  EXPECT_EQ(again.metadata, m.metadata);
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    EXPECT_EQ(again.points[i].deviation_um, m.points[i].deviation_um);
    EXPECT_EQ(again.points[i].target_mm, m.points[i].target_mm);
    EXPECT_EQ(again.points[i].time_s, m.points[i].time_s);
    for (std::size_t s = 0; s < 2; ++s) {
      const double a = again.points[i].temperatures_c[s], b = m.points[i].temperatures_c[s];
      EXPECT_TRUE((std::isnan(a) && std::isnan(b)) || a == b);
    }
  }
  EXPECT_EQ(FormatMeasurementCsv(again), FormatMeasurementCsv(m));
}

// '# compensation:' says whether the test ran through the compensation (fit refuses such a file,
// predict warns): on / off in their spellings, absent = unknown, anything else an error naming it.
TEST(MeasurementCsv, CompensationStateFromItsMetadataLine) {
  auto with = [](const std::string& line) { return ParseMeasurementCsv(line + kGood, "f.csv"); };
  EXPECT_EQ(CompensationActive(with("")), std::nullopt);
  for (const char* on : {"on", "ON", " yes", "true "}) EXPECT_EQ(CompensationActive(with(std::string("# compensation: ") + on + "\n")), true) << on;
  for (const char* off : {"off", "Off", "no", "false", "none"})
    EXPECT_EQ(CompensationActive(with(std::string("# compensation: ") + off + "\n")), false) << off;
  try {
    CompensationActive(with("# compensation: partly\n"));
    ADD_FAILURE() << "accepted 'partly'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("compensation"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("partly"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 1) << e.what();  // the '# compensation:' line, before kGood's
  }
}

// Each metadata entry remembers the line it was read from, so a refusal of its value can name it;
// entries set in code (the simulator's) have none, and setting a key again moves its line.
TEST(MeasurementCsv, MetadataRemembersItsLine) {
  auto m = ParseMeasurementCsv(std::string("# free text\n# state: warm\n") + kGood, "f.csv");
  EXPECT_EQ(m.MetaLine("state"), 2);
  EXPECT_EQ(m.MetaLine("axis"), 3);
  EXPECT_EQ(m.MetaLine("machine"), 4);
  EXPECT_EQ(m.MetaLine("date"), 0);  // absent
  m.SetMeta("axis", "Y");
  EXPECT_EQ(m.MetaLine("axis"), 0);
  m.SetMeta("axis", "Z", 9);
  EXPECT_EQ(m.MetaLine("axis"), 9);
  m.metadata.clear();
  EXPECT_EQ(m.MetaLine("state"), 0);  // no longer there
  // A key given twice: the later line wins, like its value.
  auto twice = ParseMeasurementCsv(std::string("# axis: Y\n") + kGood, "f.csv");
  EXPECT_EQ(twice.Meta("axis"), "X");
  EXPECT_EQ(twice.MetaLine("axis"), 2);
}

TEST(MeasurementCsv, MissingColumnNamesTheColumn) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm\n1,+,0\n"),
            "f.csv:1: field 'deviation_um': required column is missing from the header");
}

TEST(MeasurementCsv, NonNumericFieldNamesLineAndField) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,+,0,1.0\n1,+,25,abc\n"),
            "f.csv:3: field 'deviation_um': 'abc' is not a finite number");
}

TEST(MeasurementCsv, UnknownDirection) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,x,0,1.0\n"),
            "f.csv:2: field 'direction': 'x' is not a direction; use + or -");
}

TEST(MeasurementCsv, UnknownColumnIsAnError) {
  EXPECT_NE(ErrorOf("run,direction,target_mm,deviation_um,t_nut\n1,+,0,1,2\n").find("field 't_nut': unknown column"),
            std::string::npos);
}

TEST(MeasurementCsv, WrongFieldCount) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,+,0\n"),
            "f.csv:2: 3 fields, but the header has 4 columns");
}

TEST(MeasurementCsv, DuplicatePoint) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,+,0,1\n1,-,0,1\n2,+,0,1\n2,-,0,1\n1,+,0,2\n"),
            "f.csv:6: field 'target_mm': duplicate point: run 1 direction + target 0 mm already given on line 2");
}

TEST(MeasurementCsv, OneDirectionOnly) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,+,0,1\n1,-,0,1\n2,+,0,1\n2,-,0,1\n1,+,25,1\n2,+,25,1\n"),
            "f.csv:6: field 'direction': target 25 mm is measured only in the '+' direction; ISO 230-2 needs both");
}

TEST(MeasurementCsv, FewerThanTwoRuns) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n1,+,0,1\n1,-,0,1\n"),
            "f.csv:2: field 'run': only 1 run(s); repeatability needs at least 2 runs per direction");
}

TEST(MeasurementCsv, EmptyFile) {
  EXPECT_EQ(ErrorOf(""), "f.csv:1: no header line: the file is empty or holds only comments");
  EXPECT_EQ(ErrorOf("# axis: X\n"), "f.csv:2: no header line: the file is empty or holds only comments");
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um\n"), "f.csv: no measurement points (empty file?)");
}

TEST(MeasurementCsv, ReadingAMissingFileNamesIt) {
  try {
    ReadMeasurementCsv("/nonexistent/x.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.csv: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace trueaxis::measure

namespace trueaxis::measure {
namespace {

// Huge finite numbers and wrong units are refused with file, line and field, never evaluated
// (a 1e308 deviation made A = inf; kelvin passed the old −100…500 °C check).
TEST(MeasurementCsvPlausibility, HugeDeviationIsRefused) {
  const std::string e = ErrorOf("run,direction,target_mm,deviation_um\n1,+,0,1e308\n");
  EXPECT_NE(e.find("f.csv:2: field 'deviation_um'"), std::string::npos) << e;
  EXPECT_NE(e.find("µm"), std::string::npos) << e;
}

TEST(MeasurementCsvPlausibility, HugeTargetIsRefused) {
  EXPECT_NE(ErrorOf("run,direction,target_mm,deviation_um\n1,+,1e300,1\n").find("f.csv:2: field 'target_mm'"),
            std::string::npos);
}

TEST(MeasurementCsvPlausibility, KelvinTemperatureIsNamedAsKelvin) {
  const std::string e = ErrorOf("run,direction,target_mm,deviation_um,t_nut_c\n1,+,0,1,293.4\n");
  EXPECT_NE(e.find("f.csv:2: field 't_nut_c'"), std::string::npos) << e;
  EXPECT_NE(e.find("kelvin"), std::string::npos) << e;
}

TEST(MeasurementCsvPlausibility, PlausibleExtremesStillRead) {
  EXPECT_EQ(ErrorOf("run,direction,target_mm,deviation_um,t_nut_c\n1,+,2000,-950.5,-5\n1,-,2000,-940,60\n"
                    "2,+,2000,-950,-5\n2,-,2000,-941,60\n"),
            "");
}

}  // namespace
}  // namespace trueaxis::measure

#include <filesystem>
#include <fstream>

#include "trueaxis/core/text_file.hpp"

namespace trueaxis::measure {
namespace {

// The same four points in the encodings and dialects spreadsheets and loggers write.
const std::string kPlain =
    "run,direction,target_mm,deviation_um,t_nut_c\n1,+,0,1.5,20.25\n1,-,0,2.5,20.5\n2,+,0,1.25,20.75\n2,-,0,2.75,21\n";

Measurement ReadBytes(const std::string& bytes, const std::string& name) {
  const auto path = (std::filesystem::temp_directory_path() / ("trueaxis_dialect_" + name)).string();
  std::ofstream(path, std::ios::binary) << bytes;
  auto m = ReadMeasurementCsv(path);
  std::filesystem::remove(path);
  return m;
}

void ExpectSameAsPlain(const Measurement& m) {
  ASSERT_EQ(m.points.size(), 4u);
  EXPECT_DOUBLE_EQ(m.points[0].deviation_um, 1.5);
  EXPECT_DOUBLE_EQ(m.points[3].deviation_um, 2.75);
  EXPECT_DOUBLE_EQ(m.points[2].temperatures_c[0], 20.75);
}

TEST(MeasurementCsvDialects, SemicolonsWithDecimalCommas) {
  std::string s = kPlain;
  for (auto& c : s) c = c == ',' ? ';' : c == '.' ? ',' : c;
  ExpectSameAsPlain(ReadBytes("# note: a German Excel export, with a comma\n" + s, "semicolon.csv"));
}

TEST(MeasurementCsvDialects, QuotedFieldsAsSpreadsheetsWriteThem) {
  ExpectSameAsPlain(ReadBytes("\"run\",\"direction\",\"target_mm\",\"deviation_um\",\"t_nut_c\"\n"
                              "1,\"+\",0,\"1.5\",20.25\n1,-,0,2.5,20.5\n2,+,0,1.25,20.75\n2,-,0,2.75,21\n",
                              "quoted.csv"));
}

TEST(MeasurementCsvDialects, Utf16WithBomAndCrOnlyLineEnds) {
  std::string utf16 = "\xFF\xFE";
  for (char c : kPlain) utf16 += std::string{c, '\0'};
  ExpectSameAsPlain(ReadBytes(utf16, "utf16.csv"));
  std::string cr = kPlain;
  for (auto& c : cr) c = c == '\n' ? '\r' : c;
  ExpectSameAsPlain(ReadBytes(cr, "cr.csv"));
}

TEST(MeasurementCsvDialects, AWorkbookIsNamedNotPrintedAsBytes) {
  try {
    ReadBytes(std::string("PK\x03\x04\x14\x00\x06\x00", 8) + "[Content_Types].xml", "book.xlsx");
    ADD_FAILURE() << "an .xlsx was read as text";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("xlsx"), std::string::npos) << what;
    EXPECT_EQ(what.find("Content_Types"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace trueaxis::measure
