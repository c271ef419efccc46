// Interpolation of the once-per-lead table (inside, at the ends, per
// direction), tables from measurements and models, and the controller export
// (the 256-point limit: refused, never truncated; resampled on request).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "export/example_model.hpp"
#include "trueaxis/pitch/error_table.hpp"

namespace trueaxis::pitch {
namespace {

PitchErrorTable Linear(int n, double lead = 10) {
  PitchErrorTable t;
  t.axis = "X";
  t.lead_mm = lead;
  for (int i = 0; i < n; ++i) {
    t.position_mm.push_back(lead * i);
    t.error_up_um.push_back(2.0 * i + (i % 2 ? 1.0 : 0.0));  // not a straight line: kinks at every sample
    t.error_down_um.push_back(2.0 * i - 5.0);
  }
  return t;
}

TEST(PitchLookup, IsLinearBetweenSamplesAndExactAtThem) {
  const PitchErrorTable t = Linear(5);
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_DOUBLE_EQ(LookupError(t, t.position_mm[i], Direction::kForward).error_um, t.error_up_um[i]);
  // Between 10 (3.0) and 20 (4.0): a quarter of the way is 3.25.
  const auto l = LookupError(t, 12.5, Direction::kForward);
  EXPECT_NEAR(l.error_um, 3.25, 1e-12);
  EXPECT_FALSE(l.outside);
}

TEST(PitchLookup, HoldsTheEndValuesBeyondTheEndsAndSaysSo) {
  const PitchErrorTable t = Linear(5);
  const auto below = LookupError(t, -3, Direction::kForward);
  const auto above = LookupError(t, 47, Direction::kReverse);
  EXPECT_TRUE(below.outside);
  EXPECT_TRUE(above.outside);
  EXPECT_DOUBLE_EQ(below.error_um, t.error_up_um.front());
  EXPECT_DOUBLE_EQ(above.error_um, t.error_down_um.back());
  EXPECT_FALSE(LookupError(t, 0, Direction::kForward).outside);   // the ends themselves are inside
  EXPECT_FALSE(LookupError(t, 40, Direction::kForward).outside);
}

TEST(PitchLookup, DirectionChoosesTheCurveAcrossTheReversal) {
  const PitchErrorTable t = Linear(5);
  // At one position the two directions differ by the reversal value of the table.
  const double up = CorrectionUm(t, 15, +1), down = CorrectionUm(t, 15, -1);
  EXPECT_NEAR(up, -(3.0 + 4.0) / 2, 1e-12);
  EXPECT_NEAR(down, -(15.0 / 10 * 2 - 5), 1e-12);
  EXPECT_GT(std::abs(up - down), 4);
}

measure::Measurement SyntheticRun(double step, double travel, double lead, double harmonic_um = 2) {
  measure::Measurement m;
  m.source = "synthetic.csv";
  m.SetMeta("lead_mm", std::to_string(lead));
  m.SetMeta("reference_mm", "0");
  m.SetMeta("axis", "Y");
  for (int run = 1; run <= 2; ++run)
    for (double x = step; x <= travel + 1e-9; x += step)
      for (auto d : {Direction::kForward, Direction::kReverse}) {
        measure::MeasurementPoint p;
        p.run = run;
        p.direction = d;
        p.target_mm = x;
        // error: a lead harmonic + a slope; reverse 3 µm lower; runs differ by 0.1 µm
        p.deviation_um = harmonic_um * std::sin(2 * M_PI * x / lead) + 0.01 * x - (d == Direction::kReverse ? 3 : 0) + 0.1 * run;
        m.points.push_back(p);
      }
  return m;
}

TEST(PitchTableFromMeasurement, SamplesTheMeanAtEveryLeadPoint) {
  const auto m = SyntheticRun(1.25, 100, 5);  // lead/4
  const PitchErrorTable t = TableFromMeasurement(m, {});
  EXPECT_EQ(t.axis, "Y");
  ASSERT_EQ(t.size(), 21u);  // 0, 5, 10, … 100: the first target 1.25 is off the grid, 0 closes the table
  EXPECT_DOUBLE_EQ(t.position_mm.front(), 0);
  EXPECT_DOUBLE_EQ(t.measured_from_mm, 1.25);  // what the table vouches for
  EXPECT_DOUBLE_EQ(t.measured_to_mm, 100);
  // The sample beyond the first target holds its mean (never extrapolated).
  EXPECT_NEAR(t.error_up_um.front(), 2 * std::sin(2 * M_PI * 1.25 / 5) + 0.0125 + 0.15, 1e-9);
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double x = t.position_mm[i];
    const double truth = 2 * std::sin(2 * M_PI * x / 5) + 0.01 * x + 0.15;
    EXPECT_NEAR(t.error_up_um[i], truth, 1e-9);
    EXPECT_NEAR(t.error_down_um[i], truth - 3, 1e-9);
  }
  // Once per lead, the 2 µm harmonic is invisible to the table: that is its interpolation error
  // (between the lead points; the first lead, closed by the held sample at 0, misses it by up to 2.5 µm).
  measure::Measurement from_5 = m;
  std::erase_if(from_5.points, [](const measure::MeasurementPoint& p) { return p.target_mm < 5; });
  EXPECT_NEAR(MaxInterpolationErrorUm(t, from_5), 2.0, 0.05);
  EXPECT_LE(MaxInterpolationErrorUm(t, m), 2.55);
  TableFromMeasurementOptions four;
  four.samples_per_lead = 4;
  EXPECT_NEAR(MaxInterpolationErrorUm(TableFromMeasurement(m, four), m), 0.0, 1e-9);
}

// The table that fits the screw: a lead harmonic well above the run's scatter
// needs more than once per lead, and exactly as many as bring the table within
// the tolerance; a screw without one stays once per lead.
TEST(PitchTableFromMeasurement, SamplesPerLeadAreTheFewestThatFitTheRun) {
  const auto m = SyntheticRun(1.25, 100, 5);
  const SamplesPerLeadChoice c = ChooseSamplesPerLead(m, {});
  EXPECT_TRUE(c.within_tolerance);
  EXPECT_DOUBLE_EQ(c.tolerance_um, 0.5);  // the runs' scatter (0.07 µm) is below the floor
  EXPECT_GT(c.samples_per_lead, 1);
  EXPECT_LE(c.interpolation_error_um, c.tolerance_um);
  TableFromMeasurementOptions fewer;
  fewer.samples_per_lead = c.samples_per_lead - 1;
  EXPECT_GT(MaxInterpolationErrorUm(TableFromMeasurement(m, fewer), m), c.tolerance_um);
  EXPECT_NE(c.Describe().find(std::to_string(c.samples_per_lead) + " sample(s) per lead"), std::string::npos);

  EXPECT_EQ(ChooseSamplesPerLead(SyntheticRun(1.25, 100, 5, 0.0), {}).samples_per_lead, 1);
  // A tolerance no table of this run can meet: the densest the targets allow, said so.
  // Targets every 1.5 mm: at most 3 samples per lead of 5 mm, whose knots miss the targets.
  const SamplesPerLeadChoice tight = ChooseSamplesPerLead(SyntheticRun(1.5, 100, 5, 2.0), {}, 1e-6);
  EXPECT_FALSE(tight.within_tolerance);
  EXPECT_EQ(tight.samples_per_lead, 3);
  EXPECT_GT(tight.interpolation_error_um, 1e-6);
  EXPECT_NE(tight.Describe().find("measure with targets closer together"), std::string::npos);
}

TEST(PitchTableFromMeasurement, RefusesACoarseRunThatWouldAlias) {
  const auto m = SyntheticRun(25, 200, 5);
  try {
    TableFromMeasurement(m, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic.csv: field 'target_mm': targets up to 25 mm apart"), std::string::npos)
        << e.what();
  }
}

// A metadata value that is not a number is refused naming its line (it was taken as "no lead" and
// as "no reference" before); a missing lead still asks for --lead-mm.
TEST(PitchTableFromMeasurement, RefusesBadLeadOrReferenceMetadataNamingTheLine) {
  auto m = SyntheticRun(1, 20, 5);
  m.SetMeta("lead_mm", "five", 3);
  try {
    TableFromMeasurement(m, {});
    FAIL() << "took 'five' as a lead";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "synthetic.csv:3: field 'lead_mm': 'five' is not a number of mm");
  }
  m.SetMeta("lead_mm", "5", 3);
  m.SetMeta("reference_mm", "0,5.0", 4);
  try {
    TableFromMeasurement(m, {});
    FAIL() << "ignored a bad reference";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.field(), "reference_mm");
  }
  m.SetMeta("reference_mm", "0");
  EXPECT_EQ(TableFromMeasurement(m, {}).reference_mm, 0);
  std::erase_if(m.metadata, [](const auto& kv) { return kv.first == "lead_mm"; });
  EXPECT_THROW(TableFromMeasurement(m, {}), InputError);
}

TEST(PitchExport, RefusesMoreThanTheControllerTakesAndNamesTheSpacingThatFits) {
  const PitchErrorTable t = Linear(400, 5);  // 2 m axis, 5 mm lead
  exporter::ResampleOptions o;
  o.max_points = exporter::kLinuxCncMaxPoints;
  try {
    ResamplePitchTable(t, o, "long.pitch.csv");
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("long.pitch.csv: field '--spacing': 400 samples"), std::string::npos) << w;
    EXPECT_NE(w.find("--spacing 10 "), std::string::npos) << w;
  }
  o.spacing_mm = 10;
  const auto rr = ResamplePitchTable(t, o, "long.pitch.csv");
  EXPECT_LE(rr.table.size(), 256u);
  EXPECT_EQ(rr.table.size(), 200u);
  // The correction at kept points is exactly the table's; the loss is stated.
  EXPECT_DOUBLE_EQ(rr.table.forward_um[1], -t.error_up_um[2]);
  bool stated = false;
  for (const auto& p : rr.table.provenance) stated |= p.find("up to 1.000 um lost") != std::string::npos;
  EXPECT_TRUE(stated);
  // And LinuxCNC takes it.
  exporter::LinuxCncOptions lo;
  const std::string text = exporter::WriteLinuxCncCompFile(rr.table, lo, "t");
  EXPECT_EQ(exporter::ReadLinuxCncCompFile(text, 1, "t").size(), 200u);
}

TEST(PitchExport, AtItsOwnPointsTheCorrectionIsMinusTheError) {
  const PitchErrorTable t = Linear(20, 5);
  exporter::ResampleOptions o;
  const auto rr = ResamplePitchTable(t, o, "t");
  ASSERT_EQ(rr.table.size(), 20u);
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_DOUBLE_EQ(rr.table.forward_um[i], -t.error_up_um[i]);
    EXPECT_DOUBLE_EQ(rr.table.reverse_um[i], -t.error_down_um[i]);
  }
}

}  // namespace
}  // namespace trueaxis::pitch

namespace trueaxis::pitch {
namespace {

TEST(PitchTableFromModel, SamplesTheColdModelOncePerLeadThroughItsReference) {
  const model::AxisModel axis = exporter::testing::ExampleAxis();  // X, 0…400 mm, Px = 0
  const PitchErrorTable t = TableFromModel(axis, 12, 1, {}, "example_model.json");
  EXPECT_EQ(t.axis, "X");
  ASSERT_EQ(t.size(), 34u);  // 0, 12, … 396
  EXPECT_DOUBLE_EQ(t.position_mm.front(), 0);
  EXPECT_DOUBLE_EQ(t.position_mm.back(), 396);
  model::ThermalState cold;
  cold.use_thermal = false;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double x = t.position_mm[i];
    EXPECT_NEAR(t.error_up_um[i], model::Predict(axis, x, Direction::kForward, cold).total_um, 1e-9) << x;
    EXPECT_NEAR(t.error_down_um[i], model::Predict(axis, x, Direction::kReverse, cold).total_um, 1e-9) << x;
  }
}

}  // namespace
}  // namespace trueaxis::pitch
