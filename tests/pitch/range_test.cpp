// The range a pitch table vouches for: the calibration cycle covers the whole
// travel, the table records the range it was measured over (file, model,
// exports), holds its end values beyond it and says so, and the compensator
// raises outside_measured_range when the axis goes there.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../support/mock_hardware.hpp"
#include "pitch_test_machine.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/pitch/error_file.hpp"
#include "trueaxis/pitch/fine_cycle.hpp"
#include "trueaxis/pitch/model_table.hpp"
#include "trueaxis/pitch/proof.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::pitch {
namespace {

// One calibration run on the 130 mm test axis, shared by the tests (deterministic).
const measure::Measurement& FineRun() {
  static const measure::Measurement m = [] {
    FineSessionOptions so;
    so.cycle.runs = 2;
    return RunFineSession(testing::PitchMachine(), 0, so).measurement;
  }();
  return m;
}

// The verification: the calibration cycle again, re-homed, with `table` applied ahead.
FineSessionResult Replay(const PitchErrorTable& table) {
  FineSessionOptions so;
  so.cycle.runs = 2;
  so.table = &table;
  return RunFineSession(testing::PitchMachine(), 0, so);
}

// The same run read only between `lo` and `hi`: a calibration over part of the travel.
measure::Measurement Part(double lo, double hi) {
  measure::Measurement m = FineRun();
  m.points.clear();
  for (const auto& p : FineRun().points)
    if (p.target_mm >= lo && p.target_mm <= hi) m.points.push_back(p);
  return m;
}

TEST(PitchRange, TheCalibrationCycleCoversTheWholeTravel) {
  const auto machine = testing::PitchMachine();  // travel 130, lead 5
  FineCycleOptions o;
  const auto t = FineTargets(machine.axes[0], o);
  // The ends are reached after the shortest reversal at the travel's ends, within the tolerance.
  EXPECT_DOUBLE_EQ(t.front(), o.end_margin_mm);
  EXPECT_DOUBLE_EQ(t.back(), 130 - o.end_margin_mm);
  EXPECT_LE(o.end_margin_mm, model::kMeasuredRangeToleranceMm);
  // In between, the lead grid every lead/4.
  for (std::size_t i = 2; i + 1 < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], 1.25, 1e-9);
  EXPECT_EQ(t.size(), 105u);  // 1.25 … 128.75 and the two ends
  const auto ev = analysis::Evaluate(FineRun());
  EXPECT_DOUBLE_EQ(ev.targets.front().target_mm, 0.25);
  EXPECT_DOUBLE_EQ(ev.targets.back().target_mm, 129.75);
  // Every target approached from both sides in every run, the ends included.
  for (const auto& tr : ev.targets) {
    EXPECT_EQ(tr.n_up, 2) << tr.target_mm;
    EXPECT_EQ(tr.n_down, 2) << tr.target_mm;
  }
}

TEST(PitchRange, TheTableVouchesForTheTravelAndTheReplayStaysInside) {
  const PitchErrorTable table = TableFromMeasurement(FineRun(), {});
  EXPECT_DOUBLE_EQ(table.measured_from_mm, 0.25);
  EXPECT_DOUBLE_EQ(table.measured_to_mm, 129.75);
  // The end targets lie off the once-per-lead grid: the grid points beyond them close the table.
  EXPECT_DOUBLE_EQ(table.position_mm.front(), 0);
  EXPECT_DOUBLE_EQ(table.position_mm.back(), 130);
  EXPECT_FALSE(table.OutsideVouchedRange(0));
  EXPECT_FALSE(table.OutsideVouchedRange(130));
  // The verification replays the same cycle (reversals at the travel's ends) with the table: it never
  // leaves the range the table vouches for, so nothing is held or reported apart.
  const FineSessionResult after = Replay(table);
  EXPECT_EQ(after.outside_table_lookups, 0u);
  const PitchComparison c = ComparePitch(FineRun(), after.measurement, table);
  EXPECT_EQ(c.outside_targets, 0);
  EXPECT_EQ(c.after.targets, 105);
}

TEST(PitchRange, BeyondTheMeasuredRangeTheEndValueIsHeldAndSaid) {
  const PitchErrorTable table = TableFromMeasurement(Part(30, 100), {});
  EXPECT_DOUBLE_EQ(table.VouchedFromMm(), 30);
  EXPECT_DOUBLE_EQ(table.VouchedToMm(), 100);
  const auto at_end = LookupError(table, 100, Direction::kForward);
  EXPECT_FALSE(at_end.outside);
  EXPECT_FALSE(LookupError(table, 100 + 0.9 * model::kMeasuredRangeToleranceMm, Direction::kForward).outside);
  for (double x : {101.0, 115.0, 129.0}) {
    const auto l = LookupError(table, x, Direction::kForward);
    EXPECT_TRUE(l.outside) << x;
    EXPECT_DOUBLE_EQ(l.error_um, at_end.error_um) << x;  // held, not extrapolated
  }
  EXPECT_TRUE(LookupError(table, 5, Direction::kReverse).outside);
  EXPECT_DOUBLE_EQ(LookupError(table, 5, Direction::kReverse).error_um,
                   LookupError(table, 30, Direction::kReverse).error_um);
  // A replay over the whole travel with it: its targets outside are reported apart, not in the figures.
  const FineSessionResult after = Replay(table);
  EXPECT_GT(after.outside_table_lookups, 0u);
  const PitchComparison c = ComparePitch(FineRun(), after.measurement, table);
  EXPECT_GT(c.outside_targets, 40);  // 0.25…29.5 and 100.5…129.75 mm, beyond the tolerance
  EXPECT_LT(c.after.targets, 60);
  EXPECT_GT(c.outside_after_max_um, c.after.max_error_um);  // the held ends are what is left there
  EXPECT_NE(PitchProofResult{.c = c}.Report().find("outside the table's measured range 30…100 mm"), std::string::npos);
  // The warning for the calibration run that left part of the travel unmeasured.
  const auto w = UncoveredTravelWarning(30, 100, 130, "part.csv");
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("0…30 mm and 100…130 mm"), std::string::npos) << *w;
  EXPECT_FALSE(UncoveredTravelWarning(0.25, 129.75, 130, "whole.csv").has_value());
}

TEST(PitchRange, TheFileCarriesTheRangeAndAnOldFileLoadsWithAWarning) {
  const PitchErrorTable table = TableFromMeasurement(Part(30, 100), {});
  const std::string text = FormatPitchErrorFile(table);
  EXPECT_NE(text.find("# measured_from_mm: 30\n# measured_to_mm: 100\n"), std::string::npos) << text;
  const PitchErrorTable back = ParsePitchErrorFile(text, "x.pitch.csv");
  EXPECT_DOUBLE_EQ(back.measured_from_mm, 30);
  EXPECT_DOUBLE_EQ(back.measured_to_mm, 100);
  EXPECT_FALSE(MeasuredRangeWarning(back, "x.pitch.csv").has_value());
  // A file without the two lines still loads; its range is unknown and said so.
  std::string old = text;
  old.erase(old.find("# measured_from_mm"), std::string("# measured_from_mm: 30\n# measured_to_mm: 100\n").size());
  const PitchErrorTable o = ParsePitchErrorFile(old, "old.pitch.csv");
  EXPECT_FALSE(o.HasMeasuredRange());
  EXPECT_DOUBLE_EQ(o.VouchedFromMm(), o.position_mm.front());
  const auto w = MeasuredRangeWarning(o, "old.pitch.csv");
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("old.pitch.csv: the file does not say which range axis X was measured over"), std::string::npos) << *w;
  // Controller tables carry the range as a comment.
  exporter::ResampleOptions ro;
  const auto rr = ResamplePitchTable(back, ro, "x.pitch.csv");
  bool noted = false;
  for (const auto& p : rr.table.provenance) noted = noted || p == "measured range (vouched for): 30…100 mm; beyond it the end values are held";
  EXPECT_TRUE(noted);
  // A range beyond the samples, half a range, or an inverted one: refused naming the line.
  auto refused = [&](const std::string& bad, const std::string& expected) {
    try {
      ParsePitchErrorFile(bad, "bad.pitch.csv");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  std::string beyond = text;
  beyond.replace(beyond.find("# measured_to_mm: 100"), 21, "# measured_to_mm: 200");
  refused(beyond, "field 'measured_from_mm': the measured range 30…200 mm reaches beyond the table's samples");
  std::string half = text;
  half.erase(half.find("# measured_to_mm: 100\n"), 22);
  refused(half, "field 'measured_to_mm': give both ends of the measured range, or neither");
  std::string inverted = text;
  inverted.replace(inverted.find("# measured_to_mm: 100"), 21, "# measured_to_mm: 20");
  refused(inverted, "field 'measured_to_mm': 20 mm is not beyond measured_from_mm 30 mm");
}

// A geometric-only model of axis X with the table put into it (what `pitch into-model` writes).
std::shared_ptr<model::CompositeModel> ModelWith(const PitchErrorTable& table) {
  auto m = std::make_shared<model::CompositeModel>();
  m->machine = "pitch-test";
  model::AxisModel a;
  a.axis = "X";
  for (auto& d : a.directions) d.geometric.coefficients_um = {0.0};
  m->axes.push_back(a);
  PutTableIntoModel(table, *m, "model.json");
  return m;
}

TEST(PitchRange, TheModelFileCarriesTheRangeAndPredictHoldsBeyondIt) {
  const PitchErrorTable table = TableFromMeasurement(Part(30, 100), {});
  const auto m = ModelWith(table);
  const model::CompositeModel back = model::ModelFromJson(model::ModelToJson(*m), "m.json");
  ASSERT_TRUE(back.axes[0].HasMeasuredRange());
  EXPECT_DOUBLE_EQ(back.axes[0].measured_range_mm[0], 30);
  EXPECT_DOUBLE_EQ(back.axes[0].measured_range_mm[1], 100);
  const model::ThermalState cold{{}, std::nan(""), CoolantState::kOff, false};
  const auto inside = model::Predict(back.axes[0], 64, Direction::kForward, cold);
  EXPECT_FALSE(inside.position_outside_range);
  EXPECT_NEAR(inside.geometric_um, LookupError(table, 64, Direction::kForward).error_um, 1e-12);
  const auto beyond = model::Predict(back.axes[0], 120, Direction::kForward, cold);
  EXPECT_TRUE(beyond.position_outside_range);
  EXPECT_DOUBLE_EQ(beyond.geometric_um, model::Predict(back.axes[0], 100, Direction::kForward, cold).geometric_um);
  // An older model file (no measured_range_mm) loads as before: never flagged.
  nlohmann::json j = model::ModelToJson(*m);
  j["axes"][0].erase("measured_range_mm");
  const model::CompositeModel old = model::ModelFromJson(j, "old.json");
  EXPECT_FALSE(old.axes[0].HasMeasuredRange());
  EXPECT_FALSE(model::Predict(old.axes[0], 120, Direction::kForward, cold).position_outside_range);
  // A range that is no range is refused naming the field.
  j["axes"][0]["measured_range_mm"] = {100, 30};
  try {
    model::ModelFromJson(j, "bad.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("measured_range_mm"), std::string::npos) << e.what();
  }
}

// The compensator on a machine whose table was measured over 30…100 mm of its 130 mm travel: inside
// (and within the tolerance of the ends) no alarm; beyond, the alarm outside_measured_range with the
// end value held — the correction stays bounded, no jump, no extrapolation.
TEST(PitchRange, RunAlarmsWhenTheAxisLeavesTheMeasuredRange) {
  const PitchErrorTable table = TableFromMeasurement(Part(30, 100), {});
  trueaxis::testing::MockCnc cnc({"X"});
  trueaxis::testing::MockTemperatures temps({"ambient"}, 20.0);
  runtime::CompensatorOptions o;
  o.shaper.max_step_um = 1000;  // converge in one cycle
  o.shaper.max_correction_um = 500;
  auto comp = runtime::Compensator::ForHardware(o, cnc, temps, {});
  comp->PublishModel(ModelWith(table), "model.json");
  double t = 0;
  auto at = [&](double x) -> const runtime::CycleStatus& {
    cnc.axes[0] = {x, +1, true};
    const runtime::CycleStatus* s = nullptr;
    for (int i = 0; i < 3; ++i) s = &comp->RunCycle(cnc, temps, t += 0.01);
    return *s;
  };
  const auto& inside = at(64);
  EXPECT_EQ(inside.alarms & runtime::kAlarmOutsideMeasuredRange, 0u) << runtime::AlarmNames(inside.alarms);
  EXPECT_NEAR(inside.axes[0].desired_um, CorrectionUm(table, 64, +1), 1e-9);
  const auto& near_end = at(100 + 0.4);
  EXPECT_EQ(near_end.alarms & runtime::kAlarmOutsideMeasuredRange, 0u) << runtime::AlarmNames(near_end.alarms);
  const double held = CorrectionUm(table, 100, +1);
  for (double x : {101.0, 125.0}) {
    const auto& s = at(x);
    EXPECT_TRUE(s.alarms & runtime::kAlarmOutsideMeasuredRange) << x << ": " << runtime::AlarmNames(s.alarms);
    EXPECT_TRUE(s.axes[0].alarms & runtime::kAlarmOutsideMeasuredRange);
    EXPECT_NEAR(s.axes[0].desired_um, held, 1e-9) << x;
    EXPECT_NE(runtime::AlarmNames(s.alarms).find("outside_measured_range"), std::string::npos);
  }
  const auto& back_inside = at(80);
  EXPECT_EQ(back_inside.alarms & runtime::kAlarmOutsideMeasuredRange, 0u);
}

}  // namespace
}  // namespace trueaxis::pitch
