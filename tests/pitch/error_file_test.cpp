// The pitch error file: round trip, and every bad file refused with its
// file:line:field message.
#include <gtest/gtest.h>

#include <string>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/pitch/error_file.hpp"

namespace trueaxis::pitch {
namespace {

PitchErrorTable Sample() {
  PitchErrorTable t;
  t.axis = "X";
  t.lead_mm = 5;
  t.reference_mm = 0;
  for (int i = 1; i <= 6; ++i) {
    t.position_mm.push_back(5.0 * i);
    t.error_up_um.push_back(1.25 * i - 0.5);
    t.error_down_um.push_back(1.25 * i - 4.5);
  }
  t.provenance.push_back("test");
  return t;
}

const std::string kGood =
    "# format: trueaxis-pitch-error-v1\n"
    "# axis: X\n"
    "# lead_mm: 5\n"
    "# reference_mm: 0\n"
    "position_mm,error_up_um,error_down_um\n"
    "5,1.0,-3.0\n"
    "10,2.0,-2.0\n"
    "15,3.0,-1.0\n";

TEST(PitchErrorFile, RoundTripIsExact) {
  const PitchErrorTable t = Sample();
  const PitchErrorTable back = ParsePitchErrorFile(FormatPitchErrorFile(t), "t.pitch.csv");
  EXPECT_EQ(back.axis, "X");
  EXPECT_DOUBLE_EQ(back.lead_mm, 5);
  EXPECT_EQ(back.samples_per_lead, 1);
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_DOUBLE_EQ(back.position_mm[i], t.position_mm[i]);
    EXPECT_NEAR(back.error_up_um[i], t.error_up_um[i], 5e-5);
    EXPECT_NEAR(back.error_down_um[i], t.error_down_um[i], 5e-5);
  }
  EXPECT_EQ(back.provenance, t.provenance);
}

TEST(PitchErrorFile, ReadsTheMinimalFileAndSemicolonExports) {
  EXPECT_EQ(ParsePitchErrorFile(kGood, "g").size(), 3u);
  const std::string semicolon =
      "# axis: X\n# lead_mm: 5\nposition_mm;error_up_um;error_down_um\n5;1,5;-3\n10;2,5;-2\n";
  const auto t = ParsePitchErrorFile(semicolon, "s");
  EXPECT_DOUBLE_EQ(t.error_up_um[0], 1.5);
  EXPECT_DOUBLE_EQ(t.reference_mm, 5);  // no reference_mm: the first row is on the grid
}

struct BadCase {
  std::string name, text, expected;  // expected: the start of what()
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BadPitchFile : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadPitchFile, IsRefusedWithFileLineAndField) {
  const BadCase& c = GetParam();
  try {
    ParsePitchErrorFile(c.text, "bad.pitch.csv");
    FAIL() << "accepted: " << c.name;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).substr(0, c.expected.size()), c.expected) << e.what();
  }
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    All, BadPitchFile,
    ::testing::Values(
        BadCase{"missing_axis", Replace(kGood, "# axis: X\n", ""), "bad.pitch.csv:4: field 'axis': missing"},
        BadCase{"missing_lead", Replace(kGood, "# lead_mm: 5\n", ""), "bad.pitch.csv:4: field 'lead_mm': missing"},
        BadCase{"lead_zero", Replace(kGood, "# lead_mm: 5", "# lead_mm: 0"), "bad.pitch.csv:3: field 'lead_mm'"},
        BadCase{"lead_text", Replace(kGood, "# lead_mm: 5", "# lead_mm: five"), "bad.pitch.csv:3: field 'lead_mm': 'five' is not a number"},
        BadCase{"other_version", Replace(kGood, "v1", "v2"), "bad.pitch.csv:1: field 'format'"},
        BadCase{"correction_sign", Replace(kGood, "# axis: X\n", "# axis: X\n# sign: correction\n"), "bad.pitch.csv:3: field 'sign'"},
        BadCase{"bad_per_lead", Replace(kGood, "# axis: X\n", "# axis: X\n# samples_per_lead: 2.5\n"), "bad.pitch.csv:3: field 'samples_per_lead'"},
        BadCase{"wrong_header", Replace(kGood, "error_up_um,error_down_um", "up,down"), "bad.pitch.csv:5: field 'header'"},
        BadCase{"no_header", "# axis: X\n# lead_mm: 5\n", "bad.pitch.csv:3: field 'header': missing"},
        BadCase{"text_value", Replace(kGood, "10,2.0,", "10,abc,"), "bad.pitch.csv:7: field 'error_up_um': 'abc' is not a number"},
        BadCase{"text_position", Replace(kGood, "15,3.0", "1x,3.0"), "bad.pitch.csv:8: field 'position_mm'"},
        BadCase{"two_fields", Replace(kGood, "10,2.0,-2.0", "10,2.0"), "bad.pitch.csv:7: field 'error_down_um'"},
        BadCase{"four_fields", Replace(kGood, "10,2.0,-2.0", "10,2.0,-2.0,7"), "bad.pitch.csv:7: field 'row'"},
        BadCase{"implausible", Replace(kGood, "10,2.0,-2.0", "10,2.0,1e308"), "bad.pitch.csv:7: field 'error_down_um'"},
        BadCase{"missing_row", Replace(kGood, "10,2.0,-2.0\n", ""), "bad.pitch.csv:7: field 'position_mm': 15 mm follows 5 mm"},
        BadCase{"descending", Replace(kGood, "15,3.0", "0,3.0"), "bad.pitch.csv:8: field 'position_mm'"},
        BadCase{"off_grid", Replace(kGood, "5,1.0,-3.0", "5.5,1.0,-3.0"), "bad.pitch.csv:6: field 'position_mm': 5.5 mm is not on the grid"},
        BadCase{"one_row", Replace(Replace(kGood, "10,2.0,-2.0\n", ""), "15,3.0,-1.0\n", ""), "bad.pitch.csv:7: field 'position_mm': 1 rows"}),
    [](const ::testing::TestParamInfo<BadCase>& i) { return i.param.name; });

}  // namespace
}  // namespace trueaxis::pitch
