// Round trip per format: resample the fixed model → write the controller file
// → read it back → the correction the controller applies reproduces the
// model's correction at every table point within the format's resolution,
// and between points within the linear-interpolation error.
#include <algorithm>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "example_model.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/export/csv_table.hpp"
#include "trueaxis/export/fanuc_table.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "trueaxis/export/resample.hpp"
#include "trueaxis/export/sinumerik_table.hpp"

namespace trueaxis::exporter {
namespace {

using testing::ExampleAxis;

constexpr Direction kBoth[] = {Direction::kForward, Direction::kReverse};

std::string FieldOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "<no error>";
}

// The model's correction at the frozen state (what the table stands for).
struct ModelCorrection {
  model::AxisModel axis = ExampleAxis();
  std::vector<double> temps = {30, 26};
  CoolantState coolant = CoolantState::kOff;
  double shift_um = 0;  // zero-at-reference shift of the table
  double operator()(double x, Direction d) const {
    model::ThermalState s;
    s.key_temp_c = temps;
    s.coolant = coolant;
    return model::CorrectionUm(model::Predict(axis, x, d, s)) - shift_um;
  }
  // Bound of linear interpolation over [a, b]: h²/8 · max|f''| (f'' sampled).
  double InterpolationBound(double a, double b, Direction d) const {
    double worst = 0;
    const double e = 0.5;
    for (int k = 0; k <= 10; ++k) {
      const double x = std::clamp(a + (b - a) * k / 10.0, a + e, b - e);
      worst = std::max(worst, std::abs((*this)(x + e, d) - 2 * (*this)(x, d) + (*this)(x - e, d)) / (e * e));
    }
    return (b - a) * (b - a) / 8.0 * worst * 1.05 + 1e-9;
  }
};

ResampleOptions Options(double spacing) {
  ResampleOptions o;
  o.spacing_mm = spacing;
  o.thermal.temperatures_c = {{"nut", 30}, {"bearing", 26}};
  return o;
}

// At the points: read-back applies what the exported table applies (±res).
// Between points: within res + the interpolation bound of the model.
void ExpectReproduces(const CompensationTable& exported, const CompensationTable& read_back,
                      const ModelCorrection& model, double resolution_um, bool compare_to_model_per_direction) {
  for (double x : exported.position_mm)
    for (Direction d : kBoth) {
      EXPECT_NEAR(AppliedCorrectionUm(read_back, x, d), AppliedCorrectionUm(exported, x, d), resolution_um)
          << "at " << x << " mm dir " << DirectionSymbol(d);
      if (compare_to_model_per_direction)
        EXPECT_NEAR(AppliedCorrectionUm(read_back, x, d), model(x, d), resolution_um + 1e-9) << "at " << x;
    }
  if (!compare_to_model_per_direction) return;
  for (std::size_t i = 0; i + 1 < exported.size(); ++i) {
    const double a = exported.position_mm[i], b = exported.position_mm[i + 1];
    for (Direction d : kBoth) {
      const double bound = model.InterpolationBound(a, b, d);
      for (double t : {0.25, 0.5, 0.75}) {
        const double x = a + t * (b - a);
        EXPECT_LE(std::abs(AppliedCorrectionUm(read_back, x, d) - model(x, d)), resolution_um + bound)
            << "between " << a << " and " << b;
      }
    }
  }
}

TEST(RoundTrip, CsvIsExactInBothSigns) {
  const auto r = ResampleModel(ExampleAxis(), Options(10), "m.json");
  for (ValueSign sign : {ValueSign::kCorrection, ValueSign::kError}) {
    const auto back = ReadCsvTable(WriteCsvTable(r.table, sign, "t"), "t.csv");
    EXPECT_EQ(back.position_mm, r.table.position_mm);
    EXPECT_EQ(back.forward_um, r.table.forward_um);
    EXPECT_EQ(back.reverse_um, r.table.reverse_um);
    ExpectReproduces(r.table, back, ModelCorrection{}, 0.0, true);
  }
}

TEST(RoundTrip, LinuxCncBothFileTypesBidirectional) {
  const auto r = ResampleModel(ExampleAxis(), Options(10), "m.json");
  for (int type : {0, 1}) {
    LinuxCncOptions o;
    o.comp_file_type = type;
    const auto back = ReadLinuxCncCompFile(WriteLinuxCncCompFile(r.table, o, "t"), type, "comp.txt");
    ASSERT_EQ(back.size(), r.table.size());
    ExpectReproduces(r.table, back, ModelCorrection{}, 0.0006, true);  // 1e-6 mm printed
  }
}

TEST(RoundTrip, LinuxCncUnidirectionalFoldsTheBacklashIntoTheColumns) {
  auto o = Options(20);
  o.bidirectional = false;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  const auto back = ReadLinuxCncCompFile(WriteLinuxCncCompFile(r.table, {}, "t"), 1, "comp.txt");
  ExpectReproduces(r.table, back, ModelCorrection{}, 0.0006, false);
  EXPECT_NEAR(back.forward_um[3] - back.reverse_um[3], r.table.backlash_um, 0.0011);
  EXPECT_NE(LinuxCncIniSnippet(r.table, {}).find("# BACKLASH"), std::string::npos);
}

TEST(RoundTrip, LinuxCncTypeZeroHoldsActualPositions) {
  // The laser saw +12 µm at 100 mm: actual 100.012, trim −0.012 (docs/sign-convention.md).
  const auto t = ReadLinuxCncCompFile("0 0 0\n100.000000 100.012000 99.990000\n", 0, "c");
  EXPECT_NEAR(t.forward_um[1], -12, 1e-9);
  EXPECT_NEAR(t.reverse_um[1], 10, 1e-9);
}

TEST(RoundTrip, SinumerikTableAndTemperatureLineReproduceTheFrozenModel) {
  auto o = Options(10);
  o.bidirectional = false;
  o.thermal_in_table = false;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  ASSERT_NE(r.table.thermal_tan_beta_um_per_mm, 0);
  const auto text = WriteSinumerikEec(r.table, {}, "t");
  const auto back = ReadSinumerikEec(text, "X_EEC.INI");
  EXPECT_NEAR(back.thermal_tan_beta_um_per_mm, r.table.thermal_tan_beta_um_per_mm, 1e-6);
  EXPECT_NEAR(back.backlash_um, r.table.backlash_um, 0.0006);
  ExpectReproduces(r.table, back, ModelCorrection{}, 0.001, false);
  // Same as the model frozen into a unidirectional table (mean ± backlash/2).
  auto frozen = Options(10);
  frozen.bidirectional = false;
  const auto f = ResampleModel(ExampleAxis(), frozen, "m.json");
  for (double x : f.table.position_mm)
    for (Direction d : kBoth) EXPECT_NEAR(AppliedCorrectionUm(back, x, d), AppliedCorrectionUm(f.table, x, d), 0.001);
}

TEST(RoundTrip, SinumerikValuesAreErrorsInMillimetres) {
  CompensationTable t;
  t.axis = "X";
  t.position_mm = {0, 10};
  t.forward_um = t.reverse_um = {0, -3};  // correction −3 µm = error +3 µm
  t.bidirectional = false;
  const auto text = WriteSinumerikEec(t, {}, "t");
  EXPECT_NE(text.find("$AA_ENC_COMP[0,1,X1]=0.003000"), std::string::npos) << text;
  t.bidirectional = true;
  EXPECT_EQ(FieldOf([&] { WriteSinumerikEec(t, {}, "t"); }), "--mode");
}

TEST(RoundTrip, SinumerikNeedsAnEquidistantTable) {
  CompensationTable t;
  t.axis = "X";
  t.position_mm = {0, 10, 25};
  t.forward_um = t.reverse_um = {0, 1, 2};
  t.bidirectional = false;
  EXPECT_EQ(FieldOf([&] { WriteSinumerikEec(t, {}, "t"); }), "--spacing");
  SinumerikOptions bad;
  bad.axis_name = "x 1";
  t.position_mm = {0, 10, 20};
  EXPECT_EQ(FieldOf([&] { WriteSinumerikEec(t, bad, "t"); }), "--siemens-axis");
}

TEST(RoundTrip, FanucBidirectionalWithinRoundingOfOneIncrement) {
  auto o = Options(20);
  o.zero_at_reference = true;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  FanucOptions fo;
  const auto res = WriteFanucPitchTape(r.table, fo, "t");
  const auto back = ReadFanucPitchTape(res.tape, 1, 1.0, 0.0, "tape");
  ASSERT_TRUE(back.bidirectional);
  const double res_um = res.magnification * 1.0 / 2 + 0.5 + 1e-9;  // carried rounding + 3627 rounding
  EXPECT_LE(res.max_rounding_um, res_um);
  ModelCorrection m;
  m.shift_um = r.zero_shift_um;
  ExpectReproduces(r.table, back, m, res_um, true);
}

TEST(RoundTrip, FanucCarriedRoundingNeverAccumulates) {
  // 200 points each 0.4 units above the last: naive per-point rounding of the
  // increments gives 0 everywhere (−79.6 µm lost at the end); carried
  // rounding stays within 0.5 unit at every point.
  CompensationTable t;
  t.axis = "X";
  t.reference_position_mm = 0;
  for (int i = 0; i < 200; ++i) {
    t.position_mm.push_back(i * 5.0);
    t.forward_um.push_back(0.4 * i);
  }
  t.reverse_um = t.forward_um;
  t.bidirectional = false;
  FanucOptions o;
  o.magnification = 1;
  const auto res = WriteFanucPitchTape(t, o, "t");
  const auto back = ReadFanucPitchTape(res.tape, 1, 1.0, 0.0, "tape");
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_NEAR(AppliedCorrectionUm(back, t.position_mm[i], Direction::kForward), t.forward_um[i], 0.5 + 1e-9);
  // Reference at the first point: its own number (3620 = 3621) carries the
  // interval below the table (value 0), then 199 intervals.
  EXPECT_EQ(res.max_point_number - res.min_point_number + 1, 200);
  EXPECT_NE(res.tape.find("N10000P0\n"), std::string::npos);
}

TEST(RoundTrip, FanucUnidirectionalCarriesTheBacklashInParameter1851) {
  auto o = Options(25);
  o.zero_at_reference = true;
  o.bidirectional = false;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  const auto res = WriteFanucPitchTape(r.table, {}, "t");
  EXPECT_EQ(res.reverse_min_point_number, -1);
  EXPECT_EQ(res.tape.find("N03626"), std::string::npos);
  const auto back = ReadFanucPitchTape(res.tape, 1, 1.0, 0.0, "tape");
  EXPECT_FALSE(back.bidirectional);
  EXPECT_NEAR(back.backlash_um, r.table.backlash_um, 0.5);
  ExpectReproduces(r.table, back, ModelCorrection{}, res.magnification * 0.5 + 0.25 + 1e-9, false);
}

TEST(RoundTrip, FanucLimitsAreErrorsNamingTheOption) {
  auto o = Options(20);
  o.zero_at_reference = true;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  FanucOptions fo;
  fo.detection_unit_um = 0.3;  // 20 mm is not a whole number of 0.3 µm units
  EXPECT_EQ(FieldOf([&] { WriteFanucPitchTape(r.table, fo, "t"); }), "--spacing");
  fo = {};
  fo.magnification = 1;
  fo.point_limit = 1;
  EXPECT_EQ(FieldOf([&] { WriteFanucPitchTape(r.table, fo, "t"); }), "--fanuc-magnification");
  fo = {};
  fo.max_point_number = 30;  // 2 × 20 numbers needed
  EXPECT_EQ(FieldOf([&] { WriteFanucPitchTape(r.table, fo, "t"); }), "--spacing");
  fo = {};
  fo.max_feed_mm_per_min = 300000;  // needs ≥ 40 mm interval
  EXPECT_EQ(FieldOf([&] { WriteFanucPitchTape(r.table, fo, "t"); }), "--spacing");
  auto shifted = r.table;
  shifted.reference_position_mm = 5;  // not a table point
  EXPECT_EQ(FieldOf([&] { WriteFanucPitchTape(shifted, {}, "t"); }), "--reference-mm");
}

TEST(RoundTrip, FanucPointNumbersFollowTheManualsFormula) {
  // Reference in the middle: farthest − point = ref number − (points below) + 1.
  CompensationTable t;
  t.axis = "X";
  t.reference_position_mm = 0;
  for (int i = -8; i <= 16; ++i) {
    t.position_mm.push_back(i * 50.0);
    t.forward_um.push_back(0);
  }
  t.reverse_um = t.forward_um;
  t.bidirectional = false;
  FanucOptions o;
  o.reference_point_number = 40;
  const auto res = WriteFanucPitchTape(t, o, "t");
  EXPECT_EQ(res.min_point_number, 33);  // 40 − 400/50 + 1
  EXPECT_EQ(res.max_point_number, 56);  // 40 + 800/50
  EXPECT_NE(res.tape.find("N03621A1P33\n"), std::string::npos);
  EXPECT_NE(res.tape.find("N03624A1P50000\n"), std::string::npos);  // 50 mm in 1 µm units
}

TEST(RoundTrip, HeidenhainComBidirectionalAndUnidirectional) {
  const auto r = ResampleModel(ExampleAxis(), Options(10), "m.json");
  for (ValueSign sign : {ValueSign::kCorrection, ValueSign::kError}) {
    const auto back = ReadHeidenhainCom(WriteHeidenhainCom(r.table, "X_OFF.COM", sign, "t"), sign, "X_OFF.COM");
    EXPECT_EQ(back.axis, "X");
    ExpectReproduces(r.table, back, ModelCorrection{}, 0.1, true);  // 4 decimals mm, BACKLASH = difference
  }
  auto o = Options(25);
  o.bidirectional = false;
  const auto u = ResampleModel(ExampleAxis(), o, "m.json");
  const auto back = ReadHeidenhainCom(WriteHeidenhainCom(u.table, "X.COM", ValueSign::kCorrection, "t"),
                                      ValueSign::kCorrection, "X.COM");
  ExpectReproduces(u.table, back, ModelCorrection{}, 0.1, false);
}

TEST(RoundTrip, HeidenhainCmaHasExactlyOneActiveLine) {
  const std::vector<CmaLine> lines = {{"X_COLD.COM", false, "cold"}, {"X_FLOOD.COM", true, "coolant flood, nut=30"}};
  const auto text = WriteHeidenhainCma("X", "X.CMA", lines, "t");
  const auto back = ReadHeidenhainCma(text, "X", "X.CMA");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_FALSE(back[0].active);
  EXPECT_TRUE(back[1].active);
  EXPECT_EQ(back[1].com_file, "X_FLOOD.COM");
  EXPECT_EQ(back[1].description, "coolant flood, nut=30");
  EXPECT_EQ(FieldOf([&] { WriteHeidenhainCma("X", "X.CMA", {{"A.COM", true, ""}, {"B.COM", true, ""}}, "t"); }), "ACTIVE");
  EXPECT_EQ(FieldOf([&] { ReadHeidenhainCma(text, "Y", "X.CMA"); }), "Y");
}

TEST(Readers, BadFilesNameLineAndField) {
  auto line_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::to_string(e.line()) + ":" + e.field();
    }
    return std::string("<no error>");
  };
  EXPECT_EQ(line_of([] { ReadLinuxCncCompFile("0 0 0\n# note\n1 1 1\n", 0, "c"); }), "2:triplet");
  EXPECT_EQ(line_of([] { ReadLinuxCncCompFile("0 0 0\n-1 0 0\n", 1, "c"); }), "2:nominal");
  EXPECT_EQ(line_of([] { ReadLinuxCncCompFile("0 0 abc\n", 1, "c"); }), "1:reverse");
  std::string many;
  for (int i = 0; i < 257; ++i) many += std::to_string(i) + " 0 0\n";
  EXPECT_EQ(line_of([&] { ReadLinuxCncCompFile(many, 1, "c"); }), "0:triplet");
  EXPECT_EQ(line_of([] { ReadCsvTable("position_mm,forward_correction_um,reverse_correction_um\n1,0,0\n0,0,0\n", "c"); }),
            "3:position_mm");
  EXPECT_EQ(line_of([] { ReadCsvTable("x,y,z\n", "c"); }), "1:header");
  const std::string eec = "%_N_AX_EEC_INI\nCHANDATA(1)\n$AA_ENC_COMP[0,0,X1]=0.001\n$AA_ENC_COMP[0,1,X1]=0.002\n"
                          "$AA_ENC_COMP_STEP[0,X1]=10\n$AA_ENC_COMP_MIN[0,X1]=0\n$AA_ENC_COMP_MAX[0,X1]=20\nM17\n";
  EXPECT_EQ(line_of([&] { ReadSinumerikEec(eec, "e"); }), "0:$AA_ENC_COMP");  // 3 points expected, 2 given
  EXPECT_EQ(line_of([] { ReadSinumerikEec("CHANDATA(1)\n", "e"); }), "1:header");
  EXPECT_EQ(line_of([] { ReadFanucPitchTape("%\nN03620A1P0\nG01 X10\n%\n", 1, 1, 0, "f"); }), "3:block");
  EXPECT_EQ(line_of([] { ReadFanucPitchTape("%\nN03620A1P0\n%\n", 1, 1, 0, "f"); }), "0:3621");
  EXPECT_EQ(line_of([] { ReadHeidenhainCom("BEGIN X.COM MM\nNR    AXISPOS       X             BACKLASH\n"
                                           "0     +0.0000       +0.0010       +0.0000\n"
                                           "1     -1.0000       +0.0010       +0.0000\n[END]\n",
                                           ValueSign::kCorrection, "h"); }),
            "4:AXISPOS");
}

}  // namespace
}  // namespace trueaxis::exporter
