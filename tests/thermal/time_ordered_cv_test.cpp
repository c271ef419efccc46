// Inputs chosen the way the model is used (time_folds.hpp, linear_model.hpp): forward-chaining
// folds over one recording, leave one experiment out over several; the constant and all inputs
// always candidates; lags kept only where they earn their place; the constant where nothing beats it.
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/shared_data.hpp"
#include "test_util.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"
#include "trueaxis/thermal/time_folds.hpp"

namespace trueaxis::thermal {
namespace {

// A wander that returns toward 0 (a part's temperature drifts, it does not walk off): the drift
// is smooth (AR(1) of factor 0.95) and pulled back by 0.2 % a step.
Eigen::VectorXd Wander(std::mt19937_64& rng, int rows, double step) {
  std::normal_distribution<double> n(0.0, step);
  Eigen::VectorXd v(rows);
  double x = 0, drift = 0;
  for (int r = 0; r < rows; ++r) {
    drift = 0.95 * drift + n(rng);
    x += drift - 0.002 * x;
    v(r) = x;
  }
  return v;
}

// A long steady spindle run logged once a minute that starts with a 45 min warm-up (the error rises
// by 13.5 µm). s0, the spindle housing, follows the warm-up and afterwards a wander of its own that
// moves no error; s1 is the air, s2 the structure 2 h behind it; s3..s7 other machine parts that warm
// up with their own time constants and then wander. After the warm-up the error follows the
// structure 3 h behind the air by `steady_um_per_c` (0: only noise, 0.05 µm).
ThermalSeries WarmUpThenSteady(unsigned seed, double hours, double steady_um_per_c) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const int rows = static_cast<int>(hours * 60);
  ThermalSeries s = testing::MakeSeries(rows, 8, 60.0);
  const Eigen::VectorXd housing = Wander(rng, rows, 0.003);
  double structure = 0, lag2h = 0;
  for (int r = 0; r < rows; ++r) {
    const double m = r, warm = 5.0 * (1 - std::exp(-m / 45.0));
    const double air = 20 + std::sin(2 * M_PI * m / 1440.0 + 1.0);
    if (r == 0) structure = lag2h = air;
    structure += (air - structure) * (1 - std::exp(-1.0 / 180.0));
    lag2h += (air - lag2h) * (1 - std::exp(-1.0 / 120.0));
    s.temperatures_c(r, 0) = 25 + warm + housing(r) + 0.02 * noise(rng);
    s.temperatures_c(r, 1) = air + 0.03 * noise(rng);
    s.temperatures_c(r, 2) = lag2h + 0.5 + 0.02 * noise(rng);
    s.errors_um(r, 0) = 2.7 * warm + steady_um_per_c * (structure - 20) + 0.05 * noise(rng);
  }
  for (int c = 3; c < 8; ++c) {
    const Eigen::VectorXd wander = Wander(rng, rows, 0.003);
    const double rise_min = 10 + 15 * c;
    for (int r = 0; r < rows; ++r)
      s.temperatures_c(r, c) = 22 + c + 2.0 * (1 - std::exp(-r / rise_min)) + wander(r) + 0.02 * noise(rng);
  }
  return s;
}

// What `thermal fit` does by default: ridge, LASSO, the inputs chosen by cross-validation, lags offered.
ThermalFitOptions DefaultFit() {
  ThermalFitOptions o;
  o.kind = ModelKind::kRidge;
  o.linear.selection.max_sensors = 32;
  o.linear.choose_count_by_cv = true;
  return o;
}

// The default model's and the constant's validation RMSE on the last `fraction` of `s`.
std::pair<double, double> ChronologicalSplit(const ThermalSeries& s, double fraction) {
  EvaluationOptions eo;
  eo.models = {DefaultFit()};
  eo.validate_last_fraction = fraction;
  eo.all_sensors_reference = false;
  const ThermalEvaluation ev = EvaluateThermalModels(s, {}, eo);
  return {ev.models.front().validate.front().rmse_um, ev.constant_validate.front().rmse_um};
}

TEST(TimeFolds, ForwardChainingOverTheSecondHalfOfOneRecording) {
  const ThermalSeries s = testing::MakeSeries(1000, 1);
  const TimeFolds f = MakeTimeFolds(s);
  ASSERT_EQ(f.folds.size(), static_cast<std::size_t>(kForwardFolds));
  EXPECT_FALSE(f.by_experiment);
  EXPECT_EQ(f.Name(), "forward-chaining 5-fold");
  Eigen::Index next = 500;
  for (const auto& fold : f.folds) {
    EXPECT_EQ(fold.validate_rows.front(), next);                       // the validation blocks tile the second half
    EXPECT_EQ(static_cast<Eigen::Index>(fold.train_rows.size()), next);  // trained on every row before, none after
    EXPECT_EQ(fold.train_rows.back(), next - 1);
    next = fold.validate_rows.back() + 1;
  }
  EXPECT_EQ(next, 1000);
}

TEST(TimeFolds, TheUseLikeRowsAreTheLatestFoldInBlocksOrEveryExperiment) {
  const TimeFolds f = MakeTimeFolds(testing::MakeSeries(1000, 1));
  const auto blocks = UseLikeBlocks(f);
  ASSERT_EQ(blocks.size(), static_cast<std::size_t>(kForwardFolds));
  Eigen::Index next = f.folds.back().validate_rows.front();  // row 900: the last fold, 900..999
  for (const auto& b : blocks) {
    EXPECT_EQ(b.front(), next);
    EXPECT_EQ(b.size(), 20u);
    next = b.back() + 1;
  }
  EXPECT_EQ(next, 1000);
  ThermalSeries s = testing::MakeSeries(90, 1);
  for (int r = 0; r < 90; ++r) s.experiment.push_back(r < 30 ? 0 : r < 70 ? 1 : 2);
  const auto by_experiment = UseLikeBlocks(MakeTimeFolds(s));
  ASSERT_EQ(by_experiment.size(), 3u);
  EXPECT_EQ(by_experiment[1].size(), 40u);
  EXPECT_TRUE(UseLikeBlocks(TimeFolds{}).empty());
}

TEST(TimeFolds, OneFoldPerExperimentWhenThereAreSeveral) {
  ThermalSeries s = testing::MakeSeries(90, 1);
  for (int r = 0; r < 90; ++r) s.experiment.push_back(r < 30 ? 0 : r < 70 ? 2 : 5);  // ids as SelectRows keeps them
  const TimeFolds f = MakeTimeFolds(s);
  ASSERT_EQ(f.folds.size(), 3u);
  EXPECT_TRUE(f.by_experiment);
  EXPECT_EQ(f.folds[1].validate_rows.size(), 40u);
  EXPECT_EQ(f.folds[1].validate_rows.front(), 30);
  EXPECT_EQ(f.folds[1].train_rows.size(), 50u);
}

// The failure this choice was made for: the warm-up is where a sensor tracks the error, the long
// steady part is what the model must hold. Folds cut evenly through the recording are dominated by
// the warm-up and chose the housing sensor (and its lags), which held out did several times worse
// than the training mean. Now the default is never worse than the constant on either split.
TEST(TimeOrderedCv, AWarmUpSensorNoLongerMakesTheDefaultWorseThanTheConstant) {
  const ThermalSeries s = AddLaggedTemperatures(WarmUpThenSteady(4, 48, 0.0), DefaultLagGridS());
  for (double fraction : {0.1, 0.3}) {
    const auto [model, constant] = ChronologicalSplit(s, fraction);
    EXPECT_LE(model, constant * (1 + 1e-9)) << "validate last " << fraction;
  }
  // Fitted on the first 70 %: nothing beat the mean, so the channel is the mean — and says so.
  const ThermalSeries train = SelectRows(s, [&] {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index r = 0; r < s.Rows() * 7 / 10; ++r) rows.push_back(r);
    return rows;
  }());
  const auto m = FitThermalModel(train, DefaultFit());
  const auto& linear = dynamic_cast<const LinearThermalModel&>(*m);
  ASSERT_TRUE(linear.channel_models().front().IsConstant()) << m->Describe();
  EXPECT_TRUE(m->InputSensors().empty());
  EXPECT_NEAR(linear.channel_models().front().intercept_um, train.errors_um.col(0).mean(), 1e-9);
  EXPECT_NE(m->Describe().find("the constant (the training mean): no input beat it"), std::string::npos) << m->Describe();
  const nlohmann::json doc = m->ToJson();
  EXPECT_EQ(doc["channels"][0]["cv_choice"], "constant");
  EXPECT_NE(doc["selection"].get<std::string>().find("forward-chaining 5-fold"), std::string::npos) << doc.dump();
  EXPECT_TRUE(LinearThermalModel::FromJson(doc, "m.json", "").channel_models().front().IsConstant());
}

// Where the steady part does carry a signal of the structure (seen by s2), the lags of the warm-up
// sensors that folds through the warm-up favour are dropped, and the model still holds the mean.
TEST(TimeOrderedCv, LagsThatOnlyFitTheWarmUpAreDropped) {
  const ThermalSeries s = AddLaggedTemperatures(WarmUpThenSteady(5, 48, 1.5), DefaultLagGridS());
  for (double fraction : {0.1, 0.3}) {
    const auto [model, constant] = ChronologicalSplit(s, fraction);
    EXPECT_LE(model, constant * (1 + 1e-9)) << "validate last " << fraction;
  }
  const auto m = FitThermalModel(s, DefaultFit());
  for (const auto& name : m->InputSensors())
    EXPECT_FALSE(ParseLaggedName(name, nullptr, nullptr)) << name << "\n" << m->Describe();
}

// Where the error follows a lagged temperature (a structure behind its surface sensor), the lag is
// kept: the same cross-validation that drops lags elsewhere finds it.
TEST(TimeOrderedCv, ALagThatCarriesTheErrorIsKept) {
  std::mt19937_64 rng(8);
  std::normal_distribution<double> noise(0.0, 0.02);
  ThermalSeries s = testing::MakeSeries(24 * 60, 3, 60.0);
  double lagged = 0;
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = r / 60.0;
    const double t = 20 + (std::fmod(h, 4.0) < 2 ? 5.0 : 0.0) + (std::fmod(h, 7.0) < 3 ? 2.0 : 0.0);  // a programme
    lagged = r == 0 ? t : lagged + (t - lagged) * (1 - std::exp(-60.0 / 1800.0));  // starts at rest, like the lag
    s.temperatures_c(r, 0) = t + noise(rng);
    s.temperatures_c(r, 1) = 21 + 0.5 * std::sin(h / 3) + noise(rng);
    s.temperatures_c(r, 2) = 23 + noise(rng);
    s.errors_um(r, 0) = 3.0 * (lagged - 20) + noise(rng);
  }
  const ThermalSeries with_lags = AddLaggedTemperatures(s, {600, 1800, 5400});
  const auto m = FitThermalModel(with_lags, DefaultFit());
  bool lag = false;
  for (const auto& name : m->InputSensors()) lag = lag || name == "s0@lag1800s";
  EXPECT_TRUE(lag) << m->Describe();
  const auto& ch = dynamic_cast<const LinearThermalModel&>(*m).channel_models().front();
  EXPECT_NE(ch.cv_choice.find("sensors and lags"), std::string::npos) << ch.cv_choice;
  const auto [model, constant] = ChronologicalSplit(with_lags, 0.3);
  EXPECT_LT(model, 0.1 * constant);
}

// Where the relation weakens over the recording (the error's gain on s0 halves after 60 % of it),
// a model fitted on the past overshoots the future: the held-out folds ask for less of it, and the
// model is shrunk toward the constant by that factor — coefficients and intercept alike.
TEST(TimeOrderedCv, AModelTheFoldsOnlyPartlySupportIsShrunkTowardTheConstant) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  ThermalSeries s = testing::MakeSeries(24 * 60, 2, 60.0);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = r / 60.0, t = 20 + 2 * std::sin(2 * M_PI * h / 6);
    s.temperatures_c(r, 0) = t + 0.02 * noise(rng);
    s.temperatures_c(r, 1) = 22 + 0.02 * noise(rng);
    s.errors_um(r, 0) = (r < 0.6 * s.Rows() ? 2.0 : 1.0) * (t - 20) + noise(rng);
  }
  const auto m = FitThermalModel(s, DefaultFit());
  const auto& lm = dynamic_cast<const LinearThermalModel&>(*m);
  const auto& ch = lm.channel_models().front();
  ASSERT_NE(ch.cv_choice.find("shrunk ×"), std::string::npos) << m->Describe();
  ThermalFitOptions plain = DefaultFit();
  plain.linear.choose_count_by_cv = false;
  plain.linear.selection.max_sensors = 1;
  const auto plain_model = FitThermalModel(s, plain);
  const auto& unshrunk = dynamic_cast<const LinearThermalModel&>(*plain_model).channel_models().front();
  // s1 carries nothing: the fit on both sensors is as good as the one on s0 within the folds'
  // noise and may be averaged in (its weight on s1 is then next to nothing); s0 is there either way.
  ASSERT_FALSE(ch.inputs.empty());
  ASSERT_EQ(lm.InputSensors()[static_cast<std::size_t>(ch.inputs[0])], "s0") << m->Describe();
  ASSERT_EQ(unshrunk.k_um_per_c.size(), 1u);
  const double factor = ch.k_um_per_c[0] / unshrunk.k_um_per_c[0];
  EXPECT_GT(factor, 0.2);
  EXPECT_LT(factor, 0.9);
  // The same factor moves the intercept toward the mean: at the mean temperatures it predicts the mean.
  double at_mean = ch.intercept_um;
  for (std::size_t k = 0; k < ch.inputs.size(); ++k) {
    const std::string& name = lm.InputSensors()[static_cast<std::size_t>(ch.inputs[k])];
    const auto column = std::find(s.temperature_names.begin(), s.temperature_names.end(), name);
    ASSERT_NE(column, s.temperature_names.end()) << name;
    at_mean += ch.k_um_per_c[k] * s.temperatures_c.col(column - s.temperature_names.begin()).mean();
  }
  EXPECT_NEAR(at_mean, s.errors_um.col(0).mean(), 1e-6);
}

// The latest fold (the last tenth of the rows) is where the choice looks for what the use will be
// like. Here the error followed the sensor everywhere before it; in the latest fold it does so
// (three times as strongly) only in the first of its five blocks and stays at the mean in the
// other four. Over the whole latest fold the model still beats the constant, but only through one
// block of five: not beyond the noise, so the channel is the constant and says why. (Chosen by the
// pooled RMSE of all folds the model was kept.)
TEST(TimeOrderedCv, AModelThatBeatsTheConstantOnlyInOneBlockOfTheLatestFoldIsNotShipped) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.05);
  ThermalSeries s = testing::MakeSeries(3000, 2, 60.0);
  for (int r = 0; r < s.Rows(); ++r) {
    const double u = 2 * std::sin(2 * M_PI * r / 20.0);  // a 20 min cycle: every block sees the same swings
    s.temperatures_c(r, 0) = 20 + u + 0.02 * noise(rng);
    s.temperatures_c(r, 1) = 22 + 0.02 * noise(rng);
    const double gain = r < 2700 ? 2.0 : r < 2760 ? 6.0 : 0.0;
    s.errors_um(r, 0) = gain * u + noise(rng);
  }
  const auto m = FitThermalModel(s, DefaultFit());
  const auto& ch = dynamic_cast<const LinearThermalModel&>(*m).channel_models().front();
  EXPECT_TRUE(ch.IsConstant()) << m->Describe();
  EXPECT_NE(ch.cv_choice.find("did not beat it beyond the noise on the latest fold"), std::string::npos) << ch.cv_choice;
  EXPECT_NEAR(ch.intercept_um, s.errors_um.col(0).mean(), 1e-9);
  EXPECT_NE(m->Describe().find("the constant (the training mean): no input beat it"), std::string::npos) << m->Describe();
}

// The error follows s0; s1 (a part at rest) carries nothing. s0 alone and both sensors predict the
// later folds equally well within their noise — which of them scores best is chance — and the
// choice is their average (a linear model, its weight on s1 next to nothing), named in cv_choice.
// Heavier ridge penalties are offered on all inputs, and not for plain least squares.
TEST(TimeOrderedCv, InputSetsAsGoodWithinTheNoiseAreAveraged) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> noise(0.0, 1.0);
  ThermalSeries s = testing::MakeSeries(24 * 60, 2, 60.0);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = r / 60.0, t = 20 + 2 * std::sin(2 * M_PI * h / 5) + std::sin(2 * M_PI * h / 13);
    s.temperatures_c(r, 0) = t + 0.02 * noise(rng);
    s.temperatures_c(r, 1) = 22 + 0.02 * noise(rng);
    s.errors_um(r, 0) = 2.0 * (t - 20) + 0.05 * noise(rng);
  }
  const auto m = FitThermalModel(s, DefaultFit());
  const auto& lm = dynamic_cast<const LinearThermalModel&>(*m);
  const auto& ch = lm.channel_models().front();
  EXPECT_NE(ch.cv_choice.find(" averaged with "), std::string::npos) << m->Describe();
  ASSERT_EQ(ch.inputs.size(), 2u) << m->Describe();
  EXPECT_EQ(lm.InputSensors()[static_cast<std::size_t>(ch.inputs[0])], "s0") << m->Describe();
  EXPECT_NEAR(ch.k_um_per_c[0], 2.0, 0.05) << m->Describe();
  EXPECT_LT(std::abs(ch.k_um_per_c[1]), 0.1) << m->Describe();
  EXPECT_NE(ch.count_cv.find("all λ 0.01: "), std::string::npos) << ch.count_cv;
  EXPECT_NE(ch.count_cv.find("all λ 0.1: "), std::string::npos) << ch.count_cv;
  EXPECT_NE(m->ToJson().dump().find("averaged with"), std::string::npos);
  ThermalFitOptions mlr = DefaultFit();
  mlr.kind = ModelKind::kMlr;
  const auto least_squares = FitThermalModel(s, mlr);
  const auto& ls = dynamic_cast<const LinearThermalModel&>(*least_squares).channel_models().front();
  EXPECT_EQ(ls.count_cv.find("λ"), std::string::npos) << ls.count_cv;
}

// Validation RMSE of `model` on `channel` in a `thermal evaluate --markdown` table.
double ValidationRmse(const std::string& md, const std::string& model, const std::string& channel) {
  const auto at = md.find("| " + model + " | " + channel + " |");
  if (at == std::string::npos) return std::nan("");
  std::size_t cell = at;
  for (int k = 0; k < 5; ++k) cell = md.find('|', cell + 1);  // | model | channel | train | train max | validation
  return std::stod(md.substr(cell + 1));
}

// `thermal evaluate --validate-last F` on `csv`: per channel, the default model's and the
// constant's validation RMSE.
std::vector<std::pair<double, double>> DefaultAgainstConstant(const std::string& csv, double fraction,
                                                              const std::vector<std::string>& channels,
                                                              const std::string& dir) {
  const auto ev = testing::RunCli(fmt::format("thermal evaluate --series {} --models ridge --validate-last {} "
                                              "--markdown {}/ev.md 2>&1", csv, fraction, dir));
  EXPECT_EQ(ev.exit_code, 0) << ev.output;
  const std::string md = ReadTextFile(dir + "/ev.md");
  std::vector<std::pair<double, double>> out;
  for (const auto& c : channels)
    out.emplace_back(ValidationRmse(md, "ridge", c), ValidationRmse(md, "constant (train mean)", c));
  return out;
}

// The drawn working day of a horizontal machining centre (hmc1250, seed 3) held out on its last
// `fraction`: per channel the default model's and the constant's validation RMSE, each checked to be
// a number and the default not worse than the constant.
std::vector<std::pair<double, double>> DrawnHorizontalMachiningDay(double fraction, const std::string& dir) {
  const auto sim = testing::RunCli(fmt::format("sim recording --machine {}/examples/machines/hmc1250.toml --seed 3 "
                                               "--out {}/day.csv 2>&1", TRUEAXIS_SOURCE_DIR, dir));
  EXPECT_EQ(sim.exit_code, 0) << sim.output;
  const auto rows = DefaultAgainstConstant(dir + "/day.csv", fraction, {"X_at_938mm", "Y_at_675mm", "Z_at_750mm"}, dir);
  for (std::size_t c = 0; c < rows.size(); ++c) {
    EXPECT_TRUE(std::isfinite(rows[c].first) && std::isfinite(rows[c].second)) << "channel " << c;
    EXPECT_LE(rows[c].first, rows[c].second) << "channel " << c;
  }
  return rows;
}

// A drawn working day of a horizontal machining centre held out on its last 2.4 h (machining, dry,
// at the training mean): the forward folds of the first 21.6 h include the first hours of flood
// coolant, where every model fails and which dominated the pooled RMS, so a three-sensor model was
// chosen that lost to the constant on the held-out block by 1.5–1.6 times. Ranked by the folds'
// geometric mean, eligible only if not worse than the constant on the latest fold, the default
// must not lose to the constant on any channel.
TEST(TimeOrderedCvCli, NeverWorseThanTheConstantOnTheLastHoursOfADrawnHorizontalMachiningDay) {
  EXPECT_EQ(DrawnHorizontalMachiningDay(0.1, testing::TempDir("cv_hmc_day")).size(), 3u);
}

// The same drawn day held out on its last 30 %: the latest fold of the training part is the onset
// of flood coolant, where the input set that scored best, shrunk toward the constant, beat it in
// three of five blocks — within the noise, and the channel was the constant (16.6 µm held out
// against 7.7 µm for ridge on all inputs). Averaged with the input sets that scored as well, it
// beats the constant beyond the noise there, and held out too.
TEST(TimeOrderedCvCli, TheAverageOfEquallyGoodInputSetsHoldsWhereTheBestAloneWasNotShipped) {
  const auto rows = DrawnHorizontalMachiningDay(0.3, testing::TempDir("cv_hmc_day_30"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_LT(rows[2].first, 0.6 * rows[2].second);  // Z: the constant before
}

// The real spindle recording held out on its last 10 % (4.6 h of speed steps unlike anything
// before): on ch1 and ch2 every input set loses to the constant there, and so did the default —
// chosen where the latest training fold already said the constant was as good (ch1 better; ch2
// only within the noise). Now the default is the constant on both.
TEST(TimeOrderedCvCli, NeverWorseThanTheConstantOnTheLastTenthOfFlThermal) {
  const std::string csv = std::string(TRUEAXIS_SHARED_DATA_DIR) + "/fl_thermal/fl_thermal.csv";
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(csv);
  const std::string dir = testing::TempDir("cv_fl_last");
  const auto rows = DefaultAgainstConstant(csv, 0.1, {"ch1", "ch2"}, dir);
  for (std::size_t c = 0; c < rows.size(); ++c) {
    ASSERT_TRUE(std::isfinite(rows[c].first) && std::isfinite(rows[c].second)) << "ch" << c + 1;
    EXPECT_LE(rows[c].first, rows[c].second * (1 + 1e-6)) << "ch" << c + 1;
  }
}

// `thermal fit` prints the fallback and writes it to the model file; `thermal evaluate`'s
// validation figures are those of `thermal fit` on the training rows + `thermal predict`.
TEST(TimeOrderedCvCli, TheConstantFallbackIsPrintedWrittenAndAgreesWithEvaluate) {
  const std::string dir = testing::TempDir("cv_constant");
  const ThermalSeries s = WarmUpThenSteady(4, 48, 0.0);
  WriteThermalSeriesCsv(s, dir + "/all.csv");
  const Eigen::Index n_train = s.Rows() * 7 / 10;
  std::vector<Eigen::Index> rows;
  for (Eigen::Index r = 0; r < n_train; ++r) rows.push_back(r);
  const ThermalSeries train = SelectRows(s, rows);
  WriteThermalSeriesCsv(train, dir + "/train.csv");
  const auto fit = testing::RunCli("thermal fit --series " + dir + "/train.csv -o " + dir + "/m.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_NE(fit.output.find("note: e: no input beat the training mean on time-ordered cross-validation"),
            std::string::npos) << fit.output;
  EXPECT_NE(ReadTextFile(dir + "/m.json").find("\"cv_choice\": \"constant\""), std::string::npos);
  // The recording starts cold, 13.5 µm below the constant: what the constant does to a cold machine is said.
  const auto warn = fit.output.find("warning: e: the constant is the mean error of the state the training rows were in");
  ASSERT_NE(warn, std::string::npos) << fit.output;
  const auto from = fit.output.find(" µm from it", warn);
  ASSERT_NE(from, std::string::npos) << fit.output;
  const double offset = std::stod(fit.output.substr(fit.output.rfind(", ", from) + 2));
  EXPECT_NEAR(offset, train.errors_um.col(0).mean() - train.errors_um(0, 0), 2e-3) << fit.output;
  const auto pred = testing::RunCli("thermal predict --model " + dir + "/m.json --series " + dir + "/all.csv -o " +
                                    dir + "/p.csv");
  ASSERT_EQ(pred.exit_code, 0) << pred.output;
  // The residual column of rows n_train.. of the prediction file.
  const std::string csv = ReadTextFile(dir + "/p.csv");
  ASSERT_EQ(csv.substr(0, csv.find('\n')), "time_s,e_e_predicted_um,e_e_measured_um,e_e_residual_um");
  double ss = 0;
  Eigen::Index row = -1;
  for (std::size_t pos = csv.find('\n') + 1; pos < csv.size(); pos = csv.find('\n', pos) + 1, ++row)
    if (row + 1 >= n_train) ss += std::pow(std::stod(csv.substr(csv.rfind(',', csv.find('\n', pos)) + 1)), 2);
  ASSERT_EQ(row + 1, s.Rows());
  const double predicted_rmse = std::sqrt(ss / static_cast<double>(s.Rows() - n_train));
  const auto ev = testing::RunCli("thermal evaluate --series " + dir + "/all.csv --models ridge --validate-last 0.3 "
                                  "--markdown " + dir + "/ev.md");
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  EXPECT_NE(ev.output.find("note: e: no input beat the training mean"), std::string::npos) << ev.output;
  const std::string md = ReadTextFile(dir + "/ev.md");
  const auto at = md.find("| ridge | e |");
  ASSERT_NE(at, std::string::npos) << md;
  // | ridge | e | train RMSE | train max | validation RMSE | ...
  std::size_t cell = at;
  for (int k = 0; k < 4; ++k) cell = md.find('|', cell + 1);
  EXPECT_NEAR(std::stod(md.substr(cell + 1)), predicted_rmse, 6e-4) << md;
}

}  // namespace
}  // namespace trueaxis::thermal
