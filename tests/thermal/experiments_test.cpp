// Several recordings as experiments, the splits of `thermal evaluate` (rows, hours, experiments,
// leave-one-experiment-out), the sensor count chosen by cross-validation, and workbooks.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <xlsxwriter.h>

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/xlsx_workbook.hpp"
#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::thermal {
namespace {

// One experiment: 4 sensors, the error 2 µm/°C on s0 and -1 µm/°C on s1, plus an offset that
// differs per experiment (each run starts at its own zero).
ThermalSeries Experiment(unsigned seed, const std::string& name, int rows = 600) {
  std::mt19937_64 rng(seed);
  ThermalSeries s = testing::MakeSeries(rows, 4);
  s.source = name;
  for (int c = 0; c < 4; ++c) s.temperatures_c.col(c) = testing::RandomWalk(rng, rows, 20 + c, 0.01);
  s.errors_um.col(0) = (2.0 * s.temperatures_c.col(0).array() - 1.0 * s.temperatures_c.col(1).array()).matrix();
  return s;
}

TEST(Experiments, ConcatenationShiftsTimeAndKeepsWhichRowIsWhose) {
  ThermalSeries a = Experiment(1, "a.csv", 100), b = Experiment(2, "b.csv", 50);
  b.temperature_names[3] = "other";  // not in every experiment: dropped
  std::vector<std::string> warnings;
  const ThermalSeries j = ConcatenateExperiments({a, b}, &warnings);
  ASSERT_EQ(j.Rows(), 150);
  EXPECT_EQ(j.ExperimentCount(), 2);
  EXPECT_EQ(j.ExperimentOf(99), 0);
  EXPECT_EQ(j.ExperimentOf(100), 1);
  EXPECT_EQ(j.temperature_names.size(), 3u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("s3"), std::string::npos);
  // time keeps increasing, with the gap between runs
  EXPECT_DOUBLE_EQ(j.time_s[100] - j.time_s[99], kExperimentGapS);
  EXPECT_DOUBLE_EQ(j.time_s[101] - j.time_s[100], b.time_s[1] - b.time_s[0]);
  EXPECT_EQ(j.errors_um(120, 0), b.errors_um(20, 0));
  // speed blocks never straddle two experiments
  const auto blocks = SpeedBlocks(j);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[1].first_row, 100);
  // and SelectRows keeps the experiment of each row
  const ThermalSeries some = SelectRows(j, {5, 120});
  EXPECT_EQ(some.ExperimentOf(1), 1);
}

TEST(Experiments, OtherChannelsOrTheSameFileTwiceAreRefused) {
  ThermalSeries a = Experiment(1, "a.csv"), b = Experiment(2, "b.csv");
  b.error_names = {"z"};
  EXPECT_THROW(ConcatenateExperiments({a, b}, nullptr), InputError);
  EXPECT_THROW(ConcatenateExperiments({a, a}, nullptr), InputError);
}

ThermalFitOptions Ridge(int sensors) {
  ThermalFitOptions o;
  o.kind = ModelKind::kMlr;
  o.linear.selection.max_sensors = sensors;
  return o;
}

TEST(Evaluation, LeaveOneExperimentOutValidatesEachRowWithTheModelThatDidNotSeeIt) {
  std::vector<ThermalSeries> parts;
  for (unsigned e = 0; e < 3; ++e) parts.push_back(Experiment(10 + e, "run" + std::to_string(e) + ".csv"));
  // Each run gets its own offset, which no model can know from the temperatures.
  for (unsigned e = 0; e < 3; ++e) parts[e].errors_um.array() += 3.0 * e;
  const ThermalSeries all = ConcatenateExperiments(parts, nullptr);
  EvaluationOptions eo;
  eo.models = {Ridge(2)};
  eo.all_sensors_reference = false;
  const ThermalEvaluation ev = EvaluateThermalModels(all, {}, eo);  // several experiments: LOEO by default
  ASSERT_EQ(ev.folds.size(), 3u);
  EXPECT_EQ(ev.validate_rows.size(), static_cast<std::size_t>(all.Rows()));
  // Row 700 belongs to run1: its validation prediction is that of a model fitted on run0 + run2.
  std::vector<Eigen::Index> others;
  for (Eigen::Index r = 0; r < all.Rows(); ++r)
    if (all.ExperimentOf(r) != 1) others.push_back(r);
  const auto held_out = FitThermalModel(SelectRows(all, others), Ridge(2));
  const Eigen::MatrixXd expect = PredictSeries(*held_out, all);
  EXPECT_NEAR(ev.models[0].predicted_um(700, 0), expect(700, 0), 1e-9);
  // The run offsets are out of reach, so the held-out RMSE is about their spread, not ~0 as in-sample.
  EXPECT_GT(ev.models[0].validate[0].rmse_um, 1.0);
  EXPECT_LT(ev.models[0].train[0].rmse_um, ev.models[0].validate[0].rmse_um);
  EXPECT_NE(ev.SplitDescription().find("leave one experiment out"), std::string::npos);
}

TEST(Evaluation, SplitsByRowsHoursAndExperimentListAndOnlyOneAtATime) {
  const ThermalSeries s = Experiment(3, "one.csv", 1000);  // 15 s steps: 1000 rows = 4.16 h
  EvaluationOptions eo;
  eo.models = {Ridge(2)};
  eo.validate_rows = "800-999";
  ThermalEvaluation ev = EvaluateThermalModels(s, {}, eo);
  EXPECT_EQ(ev.validate_rows.size(), 200u);
  EXPECT_EQ(ev.train_rows.size(), 800u);
  EXPECT_EQ(ev.validate_rows.front(), 800);
  eo.validate_rows.clear();
  eo.validate_hours = "1-2";  // rows 240..480
  ev = EvaluateThermalModels(s, {}, eo);
  EXPECT_EQ(ev.validate_rows.front(), 240);
  EXPECT_EQ(ev.validate_rows.back(), 480);
  eo.validate_rows = "0-10";  // two splits at once
  EXPECT_THROW(EvaluateThermalModels(s, {}, eo), InputError);
  eo.validate_rows.clear();
  eo.validate_hours = "50-60";  // no row there
  EXPECT_THROW(EvaluateThermalModels(s, {}, eo), InputError);
  eo.validate_hours.clear();
  eo.validate_experiments = "0";  // a single experiment cannot be split by experiment
  EXPECT_THROW(EvaluateThermalModels(s, {}, eo), InputError);
  const ThermalSeries two = ConcatenateExperiments({Experiment(1, "a.csv"), Experiment(2, "b.csv")}, nullptr);
  eo.validate_experiments = "1";
  ev = EvaluateThermalModels(two, {}, eo);
  EXPECT_EQ(ev.folds.size(), 1u);
  EXPECT_EQ(ev.validate_rows.front(), 600);
  eo.validate_experiments = "0-1";  // nothing left to train on
  EXPECT_THROW(EvaluateThermalModels(two, {}, eo), InputError);
}

TEST(Evaluation, AllSensorsAndConstantAreAlwaysBeside) {
  const ThermalSeries s = Experiment(4, "one.csv", 800);
  EvaluationOptions eo;
  eo.models = {Ridge(1)};
  const ThermalEvaluation ev = EvaluateThermalModels(s, {}, eo);
  ASSERT_EQ(ev.models.size(), 2u);
  EXPECT_EQ(ev.models[0].name, "ridge (all sensors)");
  EXPECT_NE(ev.BriefReport().find("constant (train mean)"), std::string::npos);
  EXPECT_NE(ev.MarkdownTable().find("ridge (all sensors)"), std::string::npos);
}

// The recording of issue 14: many sensors that each carry part of the error. Four LASSO-chosen
// sensors lose to all of them; the count chosen by cross-validation must not.
TEST(SensorCount, ChosenByCrossValidationKeepsWhatTheDataNeeds) {
  std::mt19937_64 rng(21);
  const int rows = 1500, sensors = 12;
  ThermalSeries s = testing::MakeSeries(rows, sensors);
  std::normal_distribution<double> noise(0.0, 0.01);
  s.errors_um.setZero();
  for (int c = 0; c < sensors; ++c) {
    s.temperatures_c.col(c) = testing::RandomWalk(rng, rows, 20 + c, 0.01);
    s.errors_um.col(0) += (1.0 + 0.1 * c) * s.temperatures_c.col(c);
  }
  for (int r = 0; r < rows; ++r) s.errors_um(r, 0) += noise(rng);
  ThermalFitOptions four = Ridge(4), automatic = Ridge(32);
  automatic.linear.choose_count_by_cv = true;
  const auto m4 = FitThermalModel(s, four), ma = FitThermalModel(s, automatic);
  EXPECT_EQ(ma->InputSensors().size(), static_cast<std::size_t>(sensors));
  auto rmse = [&](const ThermalErrorModel& m) {
    return std::sqrt((s.errors_um - PredictSeries(m, s)).squaredNorm() / rows);
  };
  EXPECT_LT(rmse(*ma), 0.2 * rmse(*m4));
  // ... and where two sensors carry it all, it keeps few.
  ThermalSeries sparse = s;
  sparse.errors_um.col(0) = (2.0 * s.temperatures_c.col(3) - 1.5 * s.temperatures_c.col(7)).matrix();
  for (int r = 0; r < rows; ++r) sparse.errors_um(r, 0) += noise(rng);
  const auto ms = FitThermalModel(sparse, automatic);
  EXPECT_LE(ms->InputSensors().size(), 3u);
}

TEST(HysteresisStartUp, TheFirstRowsUseTheAllDataModelNotAHotSubModel) {
  // Heats for 4 h, holds 2 h, cools 4 h; sampled every 15 s.
  ThermalSeries s = testing::MakeSeries(10 * 240, 1);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    const double t = h < 4 ? 20 + 1.5 * h : h < 6 ? 26 : 26 - 1.5 * (h - 6);
    s.temperatures_c(r, 0) = t;
    s.errors_um(r, 0) = 4.0 * (t - 20) + (h < 4 ? -2.0 : h < 6 ? 5.0 : 2.0);  // hysteresis by interval
  }
  ThermalFitOptions o;
  o.kind = ModelKind::kHysteresis;
  o.linear.selection.max_sensors = 1;
  const auto m = FitThermalModel(s, o);
  const auto cls = m->ClassifyRows(s);
  EXPECT_EQ(cls[0], ThermalInterval::kStartUp);
  EXPECT_EQ(cls[10], ThermalInterval::kStartUp);   // 150 s of a 900 s window
  EXPECT_EQ(cls[240], ThermalInterval::kHeating);  // 1 h in
  // At start-up the prediction is the all-data model's, not the steady (hot) sub-model's.
  const auto& h = dynamic_cast<const HysteresisThermalModel&>(*m);
  const double t0[] = {20.0};
  double start[1], steady[1];
  h.Predict({std::span<const double>(t0, 1), 0.0, ThermalInterval::kStartUp}, start);
  h.Predict({std::span<const double>(t0, 1), 0.0, ThermalInterval::kSteady}, steady);
  EXPECT_GT(std::abs(start[0] - steady[0]), 1.0);
  const Eigen::MatrixXd p = PredictSeries(*m, s);
  EXPECT_DOUBLE_EQ(p(0, 0), start[0]);
}

TEST(HysteresisStartUp, ACoarseSampleIntervalWidensTheWindowAndSaysSo) {
  // The same programme logged every 10 minutes: a 900 s window holds one or two samples.
  ThermalSeries s = testing::MakeSeries(60, 1, 600.0);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    s.temperatures_c(r, 0) = h < 4 ? 20 + 1.5 * h : h < 6 ? 26 : 26 - 1.5 * (h - 6);
    s.errors_um(r, 0) = 4.0 * (s.temperatures_c(r, 0) - 20);
  }
  HysteresisFitOptions o;
  o.min_interval_samples = 5;
  std::vector<std::string> warnings;
  const HysteresisThermalModel m = FitHysteresisModel(s, o, &warnings);
  EXPECT_GE(m.classifier().window_s, kMinWindowSteps * 600.0);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("widened"), std::string::npos);
  const auto cls = m.ClassifyRows(s);
  EXPECT_EQ(cls[20], ThermalInterval::kHeating);   // 3.3 h
  EXPECT_EQ(cls[58], ThermalInterval::kCooling);   // 9.7 h
}

// A workbook written with libxlsxwriter (as Excel would save it), read back as experiments.
TEST(Workbook, EachSheetIsAnExperimentWithSpreadsheetRowNumbers) {
  const std::string dir = testing::TempDir("xlsx");
  const std::string path = dir + "/runs.xlsx";
  {
    lxw_workbook* wb = workbook_new(path.c_str());
    for (int sheet = 0; sheet < 2; ++sheet) {
      lxw_worksheet* ws = workbook_add_worksheet(wb, sheet ? "run B" : "run A");
      const char* head[] = {"time_s", "t_spindle_c", "t_bed_c", "e_z_um"};
      for (int c = 0; c < 4; ++c) worksheet_write_string(ws, 0, static_cast<lxw_col_t>(c), head[c], nullptr);
      for (int r = 1; r <= 40; ++r) {
        worksheet_write_number(ws, static_cast<lxw_row_t>(r), 0, 60.0 * r, nullptr);
        worksheet_write_number(ws, static_cast<lxw_row_t>(r), 1, 20 + 0.1 * r + sheet, nullptr);
        worksheet_write_number(ws, static_cast<lxw_row_t>(r), 2, 21 + 0.01 * r, nullptr);
        worksheet_write_number(ws, static_cast<lxw_row_t>(r), 3, 0.25 * r + 0.123456789, nullptr);
      }
    }
    lxw_worksheet* notes = workbook_add_worksheet(wb, "notes");
    worksheet_write_string(notes, 0, 0, "measured by hand", nullptr);
    ASSERT_EQ(workbook_close(wb), LXW_NO_ERROR);
  }
  ASSERT_TRUE(IsZipFile(path));
  std::vector<std::string> warnings;
  const auto runs = ReadThermalSeriesFile(path, &warnings);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[1].source, path + "[run B]");
  EXPECT_EQ(runs[1].Rows(), 40);
  EXPECT_DOUBLE_EQ(runs[1].errors_um(39, 0), 0.25 * 40 + 0.123456789);  // full precision
  EXPECT_EQ(runs[0].LineOf(0), 2);                                     // spreadsheet row 2
  ASSERT_EQ(warnings.size(), 1u);                                       // the notes sheet
  EXPECT_NE(warnings[0].find("notes"), std::string::npos);

  // A bad cell is named by sheet and spreadsheet row.
  {
    lxw_workbook* wb = workbook_new((dir + "/bad.xlsx").c_str());
    lxw_worksheet* ws = workbook_add_worksheet(wb, "log");
    worksheet_write_string(ws, 0, 0, "time_s", nullptr);
    worksheet_write_string(ws, 0, 1, "t_a_c", nullptr);
    worksheet_write_string(ws, 0, 2, "e_z_um", nullptr);
    for (int r = 1; r <= 6; ++r) {
      worksheet_write_number(ws, static_cast<lxw_row_t>(r), 0, r, nullptr);
      if (r == 4) worksheet_write_string(ws, static_cast<lxw_row_t>(r), 1, "warm", nullptr);
      else worksheet_write_number(ws, static_cast<lxw_row_t>(r), 1, 20, nullptr);
      worksheet_write_number(ws, static_cast<lxw_row_t>(r), 2, 1, nullptr);
    }
    ASSERT_EQ(workbook_close(wb), LXW_NO_ERROR);
  }
  try {
    ReadThermalSeriesFile(dir + "/bad.xlsx", nullptr);
    FAIL() << "a text in a temperature cell was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), dir + "/bad.xlsx[log]");
    EXPECT_EQ(e.line(), 5);  // spreadsheet row 5 (0-based row 4)
  }
  // A ZIP that is no workbook, and a truncated workbook.
  {
    std::string bytes = ReadFileBytes(path);
    WriteTextFile(dir + "/cut.xlsx", bytes.substr(0, bytes.size() / 2));
  }
  EXPECT_THROW(ReadThermalSeriesFile(dir + "/cut.xlsx", nullptr), InputError);
}

}  // namespace
}  // namespace trueaxis::thermal

namespace trueaxis::thermal {
namespace {

// --model auto: the kind with the lowest time-ordered CV RMSE on the rows given.
TEST(AutoModel, ChoosesHysteresisWhereHeatingAndCoolingDifferAndALinearModelWhereNot) {
  ThermalSeries loop = testing::MakeSeries(12 * 240, 2);
  double lag = 20;
  for (int r = 0; r < loop.Rows(); ++r) {  // error lags temperature by 30 min: a hysteresis loop
    const double h = loop.time_s[static_cast<std::size_t>(r)] / 3600, cycle = std::fmod(h, 6);
    const double t = cycle < 2 ? 20 + 2 * cycle : cycle < 3 ? 24 : cycle < 5 ? 24 - 2 * (cycle - 3) : 20;
    lag += (t - lag) * 15.0 / 1800.0;
    loop.temperatures_c(r, 0) = t;
    loop.temperatures_c(r, 1) = 20 + 0.1 * std::sin(h);
    loop.errors_um(r, 0) = 3.0 * (lag - 20);
  }
  ThermalFitOptions o;
  o.kind = ModelKind::kAuto;
  std::string report;
  auto m = FitThermalModel(loop, o, &report);
  EXPECT_EQ(m->Kind(), "hysteresis") << report;
  EXPECT_NE(report.find("forward-chaining 5-fold CV"), std::string::npos) << report;
  // A static linear relation: no interval structure to exploit.
  ThermalSeries linear = Experiment(7, "lin.csv", 1200);
  m = FitThermalModel(linear, o, &report);
  EXPECT_EQ(m->Kind(), "linear") << report;
}

}  // namespace
}  // namespace trueaxis::thermal
