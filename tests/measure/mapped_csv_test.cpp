// A laser software's CSV export read through a column mapping (--columns / --column-map) gives
// the same measurement as its canonical equivalent; bad mappings are refused naming file, line
// and field.
#include "trueaxis/measure/mapped_csv.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/column_map.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/measure/measurement_file.hpp"

using namespace trueaxis;
using measure::ParseColumnsOption;
using measure::ParseMappedCsv;

namespace {

// The canonical equivalent of every vendor file below: 2 runs × 2 targets × 2 directions.
const char* kCanonical =
    "# axis: X\n"
    "run,direction,target_mm,deviation_um,time_s,t_nut_c\n"
    "1,+,0,0.5,1,20.1\n"
    "1,+,100,2.25,2,20.2\n"
    "1,-,100,3.5,3,20.3\n"
    "1,-,0,1.25,4,20.4\n"
    "2,+,0,0.75,5,20.5\n"
    "2,+,100,2.5,6,20.6\n"
    "2,-,100,3.75,7,20.7\n"
    "2,-,0,1.5,8,\n";

// Long layout: a preamble, its own names and direction words, a column it does not map.
const char* kVendorLong =
    "Laser system export v2.1\n"
    "# axis: X\n"
    "Point,Run,Dir,Target [mm],Error [µm],Time [s],Nut [°C],Comment\n"
    "1,1,up,0,0.5,1,20.1,ok\n"
    "2,1,up,100,2.25,2,20.2,\n"
    "3,1,down,100,3.5,3,20.3,\n"
    "4,1,down,0,1.25,4,20.4,\n"
    "5,2,up,0,0.75,5,20.5,\n"
    "6,2,up,100,2.5,6,20.6,\n"
    "7,2,down,100,3.75,7,20.7,\n"
    "8,2,down,0,1.5,8,,\n"
    ",,,,,,,\n";
const char* kLongColumns =
    "target_mm=Target [mm],deviation_um=Error [µm],run=Run,direction=Dir,time_s=Time [s],t_nut_c=Nut [°C]";

void ExpectSame(const measure::Measurement& a, const measure::Measurement& b, bool with_extras = true) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const auto &p = a.points[i], &q = b.points[i];
    EXPECT_EQ(p.run, q.run) << i;
    EXPECT_EQ(p.direction, q.direction) << i;
    EXPECT_DOUBLE_EQ(p.target_mm, q.target_mm) << i;
    EXPECT_DOUBLE_EQ(p.deviation_um, q.deviation_um) << i;
    if (!with_extras) continue;
    EXPECT_EQ(p.time_s, q.time_s) << i;
    ASSERT_EQ(p.temperatures_c.size(), q.temperatures_c.size());
    for (std::size_t k = 0; k < p.temperatures_c.size(); ++k)
      EXPECT_TRUE(p.temperatures_c[k] == q.temperatures_c[k] ||
                  (std::isnan(p.temperatures_c[k]) && std::isnan(q.temperatures_c[k])))
          << i;
  }
  if (with_extras) EXPECT_EQ(a.sensor_names, b.sensor_names);
}

// Expects reading `text` through `columns` to fail at `line` naming `field` (and `words`).
void ExpectError(const std::string& text, const std::string& columns, const std::string& source, int line,
                 const std::string& field, const std::string& words = "") {
  try {
    ParseMappedCsv(text, "vendor.csv", ParseColumnsOption(columns));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), source) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    if (!words.empty()) EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(MappedCsv, LongLayoutReadsAsItsCanonicalEquivalent) {
  const auto canonical = measure::ParseMeasurementCsv(kCanonical, "c.csv");
  const auto mapped = ParseMappedCsv(kVendorLong, "vendor.csv", ParseColumnsOption(kLongColumns));
  ExpectSame(canonical, mapped);
  EXPECT_EQ(mapped.Meta("axis").value_or(""), "X");
  EXPECT_EQ(mapped.Meta("format").value_or(""), "mapped csv");
  EXPECT_EQ(mapped.points[2].source_line, 6);  // the file's own line, for later errors
}

TEST(MappedCsv, WideLayoutOneColumnPerRunAndDirection) {
  const std::string wide =
      "Target [mm];R1 up;R1 down;R2 up;R2 down\n"  // a decimal-comma locale export
      "0;0,5;1,25;0,75;1,5\n"
      "100;2,25;3,5;2,5;3,75\n";
  const auto map = ParseColumnsOption(
      "target_mm=Target [mm],deviation_um[1+]=R1 up,deviation_um[1-]=R1 down,deviation_um[2+]=R2 up,"
      "deviation_um[2-]=R2 down");
  const auto m = ParseMappedCsv(wide, "wide.csv", map);
  const auto c = measure::ParseMeasurementCsv(kCanonical, "c.csv");
  ASSERT_EQ(m.points.size(), c.points.size());
  // Same points in another order: compare per (run, direction, target).
  for (const auto& q : c.points) {
    int found = 0;
    for (const auto& p : m.points)
      if (p.run == q.run && p.direction == q.direction && p.target_mm == q.target_mm) {
        EXPECT_DOUBLE_EQ(p.deviation_um, q.deviation_um);
        ++found;
      }
    EXPECT_EQ(found, 1) << q.run << DirectionSymbol(q.direction) << q.target_mm;
  }
}

TEST(MappedCsv, UnitsAreConvertedOnlyWhenTheKeyNamesThem) {
  const std::string text = "Run,Dir,Pos [in],Dev [mm]\n1,+,1,0.002\n1,-,1,-0.001\n";
  const auto m = ParseMappedCsv(text, "v.csv", ParseColumnsOption("target_in=Pos [in],deviation_mm=Dev [mm],run=Run,direction=Dir"));
  ASSERT_EQ(m.points.size(), 2u);
  EXPECT_DOUBLE_EQ(m.points[0].target_mm, 25.4);
  EXPECT_DOUBLE_EQ(m.points[0].deviation_um, 2.0);
  EXPECT_DOUBLE_EQ(m.points[1].deviation_um, -1.0);
  const auto nm = ParseMappedCsv("Run,Dir,T,E\n1,+,5,1500\n", "v.csv",
                                 ParseColumnsOption("target_mm=T,deviation_nm=E,run=Run,direction=Dir"));
  EXPECT_DOUBLE_EQ(nm.points[0].deviation_um, 1.5);
  // A column whose name says mm read as µm (or inches as mm) is refused at the header.
  ExpectError(text, "target_mm=Pos [in],deviation_mm=Dev [mm],run=Run,direction=Dir", "vendor.csv", 1, "Pos [in]",
              "map it as target_in");
  ExpectError(text, "target_in=Pos [in],deviation_um=Dev [mm],run=Run,direction=Dir", "vendor.csv", 1, "Dev [mm]",
              "map it as deviation_mm");
  ExpectError("Run,Dir,T,E,Temp [°F]\n1,+,0,1,70\n", "target_mm=T,deviation_um=E,run=Run,direction=Dir,t_a_c=Temp [°F]",
              "vendor.csv", 1, "Temp [°F]", "convert the column to °C");
}

TEST(MappedCsv, DirectionWordsRecognisedOrExplicit) {
  const std::string cols = "target_mm=T,deviation_um=E,run=R,direction=D";
  for (const char* fwd : {"+", "up", "fwd", "forward", "1", "+1", "POS"}) {
    const auto m = ParseMappedCsv(std::string("R,D,T,E\n1,") + fwd + ",0,1\n", "v.csv", ParseColumnsOption(cols));
    EXPECT_EQ(m.points[0].direction, Direction::kForward) << fwd;
  }
  for (const char* rev : {"-", "down", "rev", "reverse", "backward", "-1", "neg"}) {
    const auto m = ParseMappedCsv(std::string("R,D,T,E\n1,") + rev + ",0,1\n", "v.csv", ParseColumnsOption(cols));
    EXPECT_EQ(m.points[0].direction, Direction::kReverse) << rev;
  }
  // An unrecognised word names the line and the column.
  ExpectError("R,D,T,E\n1,+,0,1\n1,aller,0,1\n", cols, "vendor.csv", 3, "D", "'aller' is not a direction");
  // The mapping's own words.
  const auto m = ParseMappedCsv("R,D,T,E\n1,aller,0,1\n1,retour,0,2\n", "v.csv",
                                ParseColumnsOption(cols + ",forward=aller|hin,reverse=retour"));
  EXPECT_EQ(m.points[0].direction, Direction::kForward);
  EXPECT_EQ(m.points[1].direction, Direction::kReverse);
}

TEST(MappedCsv, BadMappingsAreRefusedNamingFileLineField) {
  const std::string cols = kLongColumns;
  // An unknown key, a key given twice, a word for both directions: the option named.
  ExpectError(kVendorLong, "target=Target [mm]", "--columns", 0, "target", "unknown mapping key");
  ExpectError(kVendorLong, cols + ",run=Point", "--columns", 0, "run", "given twice");
  ExpectError(kVendorLong, cols + ",forward=x,reverse=x", "--columns", 0, "reverse", "other direction");
  ExpectError(kVendorLong, "deviation_um[0+]=x,target_mm=T", "--columns", 0, "deviation_um[0+]");
  // A mapped column the file lacks: named with the line closest to a header.
  ExpectError(kVendorLong, "target_mm=Target [mm],deviation_um=Error [um],run=Run,direction=Dir", "vendor.csv", 3,
              "Error [um]", "not in the header");
  // No run or direction column: says what is needed instead of guessing.
  ExpectError(kVendorLong, "target_mm=Target [mm],deviation_um=Error [µm],direction=Dir", "--columns", 0, "run",
              "map run=<column>");
  ExpectError(kVendorLong, "target_mm=Target [mm],deviation_um=Error [µm],run=Run", "--columns", 0, "direction",
              "deviation_um[1+]");
  // Bad values: the file's line and column.
  ExpectError("Run,Dir,Target [mm],Error [µm]\n1,up,0,abc\n", "target_mm=Target [mm],deviation_um=Error [µm],run=Run,direction=Dir",
              "vendor.csv", 2, "Error [µm]", "not a finite number");
  ExpectError("Run,Dir,Target [mm],Error [µm]\n0,up,0,1\n", "target_mm=Target [mm],deviation_um=Error [µm],run=Run,direction=Dir",
              "vendor.csv", 2, "Run", "not a run number");
  ExpectError("Run,Dir,T,E\n1,up,0\n", "target_mm=T,deviation_um=E,run=Run,direction=Dir", "vendor.csv", 2, "",
              "3 fields, but the header (line 1) has 4");
}

TEST(MappedCsv, MillimetresUnderAMicrometreColumnStillWarn) {
  // No unit in the column names: the values alone tell (the warning every reader gives).
  std::string text = "R,D,T,E\n";
  for (int run = 1; run <= 2; ++run)
    for (const char* d : {"+", "-"})
      for (int t = 0; t <= 200; t += 100) text += std::to_string(run) + "," + d + "," + std::to_string(t) + ",0.004\n";
  const auto m = ParseMappedCsv(text, "v.csv", ParseColumnsOption("target_mm=T,deviation_um=E,run=R,direction=D"));
  EXPECT_TRUE(measure::DeviationUnitWarning(m).has_value());
}

TEST(MappedCsv, TomlMapFileTakesTheSameKeysWithLines) {
  const std::string toml =
      "# my laser software\n"
      "target_mm = \"Target [mm]\"\n"
      "deviation_um = \"Error [µm]\"\n"
      "run = \"Run\"\n"
      "direction = \"Dir\"\n"
      "time_s = \"Time [s]\"\n"
      "t_nut_c = \"Nut [°C]\"\n"
      "forward = [\"up\", \"U\"]\n"
      "[metadata]\n"
      "machine = \"VMC-850\"\n";
  const auto map = measure::ParseColumnMapToml(toml, "map.toml");
  const auto m = ParseMappedCsv(kVendorLong, "vendor.csv", map);
  ExpectSame(measure::ParseMeasurementCsv(kCanonical, "c.csv"), m);
  EXPECT_EQ(m.Meta("machine").value_or(""), "VMC-850");
  try {
    measure::ParseColumnMapToml("target_mm = \"T\"\ndeviaton_um = \"E\"\n", "map.toml");
    FAIL() << "a misspelt key must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "map.toml");
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "deviaton_um");
  }
  // The file's own metadata and the map's must agree.
  try {
    ParseMappedCsv(std::string("# machine: other\n") + kVendorLong, "vendor.csv", map);
    FAIL() << "conflicting metadata must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.field(), "machine");
  }
}

TEST(MappedCsv, DetectionReadsCanonicalAndEcmcFilesAsThemselvesEvenWithAMapping) {
  measure::MeasurementReadOptions read;
  read.columns = ParseColumnsOption(kLongColumns);
  EXPECT_EQ(measure::DetectMeasurementFormat("a.csv", kCanonical, read), measure::MeasurementFormat::kCanonicalCsv);
  EXPECT_EQ(measure::DetectMeasurementFormat("a.csv", kVendorLong, read), measure::MeasurementFormat::kMappedCsv);
  EXPECT_EQ(measure::DetectMeasurementFormat("a.csv", kVendorLong), measure::MeasurementFormat::kCanonicalCsv);
  EXPECT_EQ(measure::DetectMeasurementFormat("a.dat", "TGT_DATA[1]=0\n", read), measure::MeasurementFormat::kEcmcDat);
  ExpectSame(measure::ParseMeasurement(kCanonical, "a.csv", read), measure::ParseMeasurement(kVendorLong, "v.csv", read));
  // Without a mapping a vendor file gets the canonical error, which points at the mapping.
  try {
    measure::ParseMeasurement(kVendorLong, "v.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "Laser system export v2.1");
    EXPECT_NE(std::string(e.what()).find("--columns"), std::string::npos) << e.what();
  }
}
