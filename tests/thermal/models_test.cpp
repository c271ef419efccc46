#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/core/text_file.hpp"

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/hysteresis_model.hpp"
#include "trueaxis/thermal/linear_model.hpp"
#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/pso_bp_network.hpp"
#include "trueaxis/thermal/sensor_selection.hpp"
#include "trueaxis/thermal/series_cleaning.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::thermal {
namespace {

double Rmse(const ThermalSeries& s, const Eigen::MatrixXd& p) {
  return std::sqrt((s.errors_um - p).squaredNorm() / static_cast<double>(s.errors_um.size()));
}

TEST(LinearModel, RecoversAKnownLinearRelation) {
  std::mt19937_64 rng(11);
  ThermalSeries s = testing::MakeSeries(400, 5);
  for (int c = 0; c < 5; ++c) s.temperatures_c.col(c) = testing::RandomWalk(rng, 400, 20 + c, 0.02);
  s.errors_um.col(0) = (3.0 + 2.0 * s.temperatures_c.col(1).array() - 1.5 * s.temperatures_c.col(3).array()).matrix();
  LinearFitOptions o;
  o.selection.method = SelectionMethod::kAll;
  LinearThermalModel m = FitLinearModel(s, o);
  ASSERT_EQ(m.channel_models().size(), 1u);
  const LinearChannel& ch = m.channel_models()[0];
  for (std::size_t k = 0; k < ch.inputs.size(); ++k) {
    const std::string& name = m.InputSensors()[static_cast<std::size_t>(ch.inputs[k])];
    const double expect = name == "s1" ? 2.0 : name == "s3" ? -1.5 : 0.0;
    EXPECT_NEAR(ch.k_um_per_c[k], expect, 1e-8) << name;
  }
  EXPECT_NEAR(ch.intercept_um, 3.0, 1e-6);
  EXPECT_LT(Rmse(s, PredictSeries(m, s)), 1e-8);
  // Ridge shrinks, but a tiny penalty stays close; a huge one flattens.
  o.ridge_lambda = 1e-6;
  LinearThermalModel r = FitLinearModel(s, o);
  EXPECT_LT(Rmse(s, PredictSeries(r, s)), 1e-3);
  o.ridge_lambda = 1e6;
  LinearThermalModel flat = FitLinearModel(s, o);
  for (double k : flat.channel_models()[0].k_um_per_c) EXPECT_LT(std::abs(k), 1e-3);
}

// Two informative sensors (slow drifts, as heated structure), a redundant
// copy of the first, and seven noise sensors that wander around their own
// level with a common ambient component: the selection must pick the two
// drivers.
ThermalSeries SelectionFixture(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int n = 600;
  ThermalSeries s = testing::MakeSeries(n, 10);
  std::normal_distribution<double> small(0.0, 0.05), unit(0.0, 1.0);
  Eigen::VectorXd a = testing::RandomWalk(rng, n, 25, 0.02), b = testing::RandomWalk(rng, n, 30, 0.02);
  double ambient = 0;
  for (int r = 0; r < n; ++r) {
    ambient = 0.95 * ambient + 0.1 * unit(rng);
    s.temperatures_c(r, 0) = a(r);
    s.temperatures_c(r, 1) = a(r) + small(rng);  // redundant neighbour of a
    s.temperatures_c(r, 4) = b(r);
    for (int c : {2, 3, 5, 6, 7, 8, 9}) s.temperatures_c(r, c) = 20 + c + ambient + small(rng);
    s.errors_um(r, 0) = 4.0 * (a(r) - 25) - 3.0 * (b(r) - 30) + small(rng);
  }
  return s;
}

TEST(SensorSelection, PicksTheInformativeSensorsOutOfNoise) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    ThermalSeries s = SelectionFixture(seed);
    SensorSelectionOptions lasso;
    lasso.method = SelectionMethod::kLasso;
    lasso.max_sensors = 2;
    std::vector<int> got = SelectSensors(s.temperatures_c, s.errors_um.col(0), lasso).sensors;
    ASSERT_EQ(got.size(), 2u);
    EXPECT_TRUE(std::count(got.begin(), got.end(), 4)) << "lasso, seed " << seed;
    EXPECT_TRUE(std::count(got.begin(), got.end(), 0) || std::count(got.begin(), got.end(), 1)) << "lasso, seed " << seed;

    SensorSelectionOptions clusters;
    clusters.method = SelectionMethod::kCorrelationClusters;
    clusters.max_sensors = 3;  // a-like, b, ambient noise
    SensorSelection sel = SelectSensors(s.temperatures_c, s.errors_um.col(0), clusters);
    ASSERT_EQ(sel.sensors.size(), 3u);
    std::vector<int> top2(sel.sensors.begin(), sel.sensors.begin() + 2);
    std::sort(top2.begin(), top2.end());
    if (top2[0] == 1) top2[0] = 0;  // a or its copy: either represents the a-cluster
    EXPECT_EQ(top2, (std::vector<int>{0, 4})) << "clusters, seed " << seed;
    EXPECT_EQ(sel.cluster[0], sel.cluster[1]);  // the copy clusters with its original
    EXPECT_EQ(sel.cluster[2], sel.cluster[9]);  // the noise sensors cluster together
    // and the model on the chosen sensors explains the error (to the copy's
    // 0.05 °C noise times 4 µm/°C at worst)
    LinearFitOptions lo;
    lo.selection = clusters;
    LinearThermalModel m = FitLinearModel(s, lo);
    EXPECT_LT(Rmse(s, PredictSeries(m, s)), 0.25);
  }
}

TEST(SensorSelection, LassoCoordinateDescentMatchesLeastSquaresAtZeroPenalty) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n01;
  Eigen::MatrixXd x(200, 3);
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 3; ++c) x(r, c) = n01(rng);
  x = x.rowwise() - x.colwise().mean();
  for (int c = 0; c < 3; ++c) x.col(c) /= std::sqrt(x.col(c).squaredNorm() / 200);
  Eigen::VectorXd y = x * Eigen::Vector3d(1.0, -2.0, 0.5);
  Eigen::VectorXd beta;
  LassoCoordinateDescent(x, y, 0.0, 10000, 1e-12, &beta);
  EXPECT_NEAR(beta(0), 1.0, 1e-8);
  EXPECT_NEAR(beta(1), -2.0, 1e-8);
  LassoCoordinateDescent(x, y, 10.0, 10000, 1e-12, &beta);  // above lambda_max: all zero
  EXPECT_EQ(beta.cwiseAbs().maxCoeff(), 0.0);
}

// A nonlinear, 2-input relation for the network.
ThermalSeries NetworkFixture() {
  std::mt19937_64 rng(21);
  ThermalSeries s = testing::MakeSeries(120, 2);
  s.temperatures_c.col(0) = testing::RandomWalk(rng, 120, 25, 0.03);
  s.temperatures_c.col(1) = testing::RandomWalk(rng, 120, 22, 0.03);
  for (int r = 0; r < 120; ++r)
    s.errors_um(r, 0) = 5.0 * std::tanh(s.temperatures_c(r, 0) - 25) + 1.5 * (s.temperatures_c(r, 1) - 22);
  return s;
}

PsoBpOptions SmallNetwork() {
  PsoBpOptions o;
  o.temperature_inputs = 2;
  o.particles = 30;
  o.pso_iterations = 30;
  o.epochs = 200;
  o.learning_rate = 0.05;
  o.seed = 7;
  return o;
}

TEST(PsoBpNetwork, SeedDefaultsAreTheSeed003Configuration) {
  PsoBpOptions o;
  EXPECT_EQ(o.hidden_units, 7);
  EXPECT_DOUBLE_EQ(o.learning_rate, 0.01);
  EXPECT_EQ(o.epochs, 500);
  EXPECT_EQ(o.particles, 200);
  EXPECT_DOUBLE_EQ(o.c1, 0.8);
  EXPECT_DOUBLE_EQ(o.c2, 0.8);
  EXPECT_DOUBLE_EQ(o.inertia, 0.5);
  EXPECT_DOUBLE_EQ(o.velocity_limit, 1.0);
  EXPECT_EQ(o.Dimension(2), 29);  // 2*7 + 7 + 7*1 + 1
}

TEST(PsoBpNetwork, SameSeedSameNetworkOtherSeedOtherNetwork) {
  ThermalSeries s = NetworkFixture();
  PsoBpOptions o = SmallNetwork();
  PsoBpNetworkModel a = FitPsoBpNetwork(s, o), b = FitPsoBpNetwork(s, o);
  EXPECT_EQ(a.networks()[0].Parameters(), b.networks()[0].Parameters());
  o.seed = 8;
  PsoBpNetworkModel c = FitPsoBpNetwork(s, o);
  EXPECT_NE(a.networks()[0].Parameters(), c.networks()[0].Parameters());
}

TEST(PsoBpNetwork, SwarmAndBackPropagationBothReduceTheError) {
  ThermalSeries s = NetworkFixture();
  PsoBpFitSummary sum;
  PsoBpNetworkModel m = FitPsoBpNetwork(s, SmallNetwork(), &sum);
  ASSERT_EQ(sum.channels.size(), 1u);
  const auto& c = sum.channels[0];
  EXPECT_EQ(c.dimension, 29);
  ASSERT_EQ(c.pso_best_sse.size(), 31u);
  EXPECT_LT(c.pso_best_sse.back(), 0.5 * c.pso_best_sse.front());
  for (std::size_t i = 1; i < c.pso_best_sse.size(); ++i) EXPECT_LE(c.pso_best_sse[i], c.pso_best_sse[i - 1]);
  EXPECT_LT(c.sse_after_bp, c.sse_after_pso);
  // the network beats predicting the mean by a wide margin
  const double sd = std::sqrt((s.errors_um.array() - s.errors_um.mean()).square().mean());
  EXPECT_LT(Rmse(s, PredictSeries(m, s)), 0.5 * sd);
  EXPECT_NEAR(c.train_rmse_um, Rmse(s, PredictSeries(m, s)), 1e-9);
}

TEST(PsoBpNetwork, Seed003ZAxisTableWithTheExactConfiguration) {
  ThermalSeries raw = ReadThermalSeriesCsv(std::string(TRUEAXIS_SOURCE_DIR) + "/data/thermal/seed003_z_axis.csv");
  ThermalSeries s = CleanSeries(SelectErrorChannels(raw, {"mean"}), {}, nullptr);
  PsoBpOptions o;  // the seed's configuration: 2-7-1 on temperature + position
  PsoBpFitSummary sum;
  PsoBpNetworkModel m = FitPsoBpNetwork(s, o, &sum);
  ASSERT_EQ(m.networks().size(), 1u);
  EXPECT_EQ(m.networks()[0].NetworkInputs(), 2);
  EXPECT_TRUE(m.networks()[0].uses_position);
  EXPECT_EQ(m.networks()[0].Parameters().size(), 29u);
  Eigen::MatrixXd p = PredictSeries(m, s);
  const double max_abs = (s.errors_um - p).cwiseAbs().maxCoeff();
  // The paper reports max |residual| 0.34 µm; the error spans 14 µm. We hold
  // the reproduction to under 1 µm (bench/results/thermal.md has the numbers).
  EXPECT_LT(max_abs, 1.0);
  EXPECT_GT(s.errors_um.cwiseAbs().maxCoeff(), 14.0);
}

TEST(Hysteresis, ClassifiesSyntheticHeatingSteadyCooling) {
  // 2 h heating at 2 °C/h, 2 h steady, 2 h cooling at -1.5 °C/h, 15 s steps.
  ThermalSeries s = testing::MakeSeries(6 * 240, 1);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    s.temperatures_c(r, 0) = h < 2 ? 20 + 2 * h : h < 4 ? 24 : 24 - 1.5 * (h - 4);
  }
  IntervalClassifierOptions o;  // 900 s window, 0.3 °C/h
  auto cls = ClassifyIntervals(s.time_s, s.temperatures_c.col(0), o);
  auto at = [&](double hours) { return cls[static_cast<std::size_t>(hours * 240)]; };
  EXPECT_EQ(at(1.0), ThermalInterval::kHeating);
  EXPECT_EQ(at(1.9), ThermalInterval::kHeating);
  EXPECT_EQ(at(2.5), ThermalInterval::kSteady);  // window (15 min) has left the ramp
  EXPECT_EQ(at(3.9), ThermalInterval::kSteady);
  EXPECT_EQ(at(4.5), ThermalInterval::kCooling);
  EXPECT_EQ(at(5.9), ThermalInterval::kCooling);
  // exact trend on a ramp
  auto trend = TemperatureTrendCPerH(s.time_s, s.temperatures_c.col(0), 900);
  EXPECT_NEAR(trend[240], 2.0, 1e-9);
  EXPECT_NEAR(trend[5 * 240], -1.5, 1e-9);
  // and with noise on the trace, far from the ramps, the class still holds
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.02);
  Eigen::VectorXd noisy = s.temperatures_c.col(0);
  for (int r = 0; r < noisy.size(); ++r) noisy(r) += noise(rng);
  auto ncls = ClassifyIntervals(s.time_s, noisy, o);
  int wrong = 0;
  for (double h = 0.5; h < 6; h += 0.25)
    if (std::abs(h - 2) > 0.3 && std::abs(h - 4) > 0.3 && ncls[static_cast<std::size_t>(h * 240)] != at(h)) ++wrong;
  EXPECT_EQ(wrong, 0);
}

TEST(Hysteresis, TrackerClassifiesSampleBySampleLikeTheBatchRule) {
  std::mt19937_64 rng(8);
  ThermalSeries s = testing::MakeSeries(3000, 1);
  s.temperatures_c.col(0) = testing::RandomWalk(rng, 3000, 25, 0.01);
  IntervalClassifierOptions o;
  auto batch = ClassifyIntervals(s.time_s, s.temperatures_c.col(0), o);
  IntervalTracker tracker(o);
  int heating = 0, cooling = 0;
  for (int r = 0; r < 3000; ++r) {
    const ThermalInterval got = tracker.Push(s.time_s[static_cast<std::size_t>(r)], s.temperatures_c(r, 0));
    ASSERT_EQ(got, batch[static_cast<std::size_t>(r)]) << "row " << r;
    heating += got == ThermalInterval::kHeating;
    cooling += got == ThermalInterval::kCooling;
  }
  EXPECT_GT(heating, 0);  // the walk really visits all three intervals
  EXPECT_GT(cooling, 0);
}

TEST(Hysteresis, PerIntervalModelsBeatOneModelOnAHysteresisLoop) {
  // The error lags temperature: e = 3*T_lag with a 30 min first-order lag, so
  // at the same temperature heating and cooling give different errors.
  ThermalSeries s = testing::MakeSeries(12 * 240, 2);
  double lag = 20;
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    const double cycle = std::fmod(h, 6);
    const double t = cycle < 2 ? 20 + 2 * cycle : cycle < 3 ? 24 : cycle < 5 ? 24 - 2 * (cycle - 3) : 20;
    lag += (t - lag) * 15.0 / 1800.0;
    s.temperatures_c(r, 0) = t;
    s.temperatures_c(r, 1) = 20 + 0.1 * std::sin(h);  // a bystander
    s.errors_um(r, 0) = 3.0 * (lag - 20);
  }
  ThermalFitOptions one;
  one.kind = ModelKind::kRidge;
  one.linear.selection.max_sensors = 2;
  ThermalFitOptions hyst = one;
  hyst.kind = ModelKind::kHysteresis;
  auto single = FitThermalModel(s, one);
  auto split = FitThermalModel(s, hyst);
  const double e1 = Rmse(s, PredictSeries(*single, s)), e2 = Rmse(s, PredictSeries(*split, s));
  EXPECT_LT(e2, 0.7 * e1) << "single " << e1 << " per-interval " << e2;
  // Hysteresis needs time.
  ThermalSeries untimed = s;
  untimed.has_time = false;
  EXPECT_THROW(FitThermalModel(untimed, hyst), InputError);
}

TEST(ModelJson, EveryKindRoundTripsWithIdenticalPredictions) {
  ThermalSeries s = SelectionFixture(1);
  for (int r = 0; r < s.Rows(); ++r)  // give the trend something to classify
    s.temperatures_c(r, 0) += 2.0 * std::sin(r / 60.0);
  const std::string dir = testing::TempDir("json");
  for (ModelKind k : {ModelKind::kMlr, ModelKind::kRidge, ModelKind::kPsoBp, ModelKind::kHysteresis}) {
    ThermalFitOptions o;
    o.kind = k;
    o.network = SmallNetwork();
    o.hysteresis.min_interval_samples = 10;
    auto m = FitThermalModel(s, o);
    const std::string path = dir + "/" + ModelKindName(k) + ".json";
    WriteThermalModelFile(*m, path);
    auto back = ReadThermalModelFile(path);
    EXPECT_EQ(back->Kind(), m->Kind());
    EXPECT_EQ(back->InputSensors(), m->InputSensors());
    EXPECT_EQ(PredictSeries(*back, s), PredictSeries(*m, s)) << ModelKindName(k);
  }
}

TEST(ModelJson, BadModelFilesNameTheField) {
  auto expect_field = [](const nlohmann::json& doc, const std::string& field) {
    try {
      ThermalModelFromJson(doc, "m.json");
      FAIL() << doc.dump();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  expect_field({{"kind", "magic"}}, "kind");
  expect_field({{"kind", "linear"}, {"sensors", {"a"}}, {"channels", nlohmann::json::array()}}, "ridge_lambda");
  expect_field({{"kind", "linear"},
                {"ridge_lambda", 0},
                {"sensors", {"a"}},
                {"channels", {{{"name", "x"}, {"sensors", {"b"}}, {"k_um_per_c", {1.0}}, {"intercept_um", 0}}}}},
               "channels[0].sensors[0]");
  expect_field({{"kind", "linear"},
                {"ridge_lambda", 0},
                {"sensors", {"a"}},
                {"channels", {{{"name", "x"}, {"sensors", {"a"}}, {"k_um_per_c", {1.0, 2.0}}, {"intercept_um", 0}}}}},
               "channels[0].k_um_per_c");
  // A name listed twice: two prediction columns of one name, or one reading fed to two coefficients.
  const nlohmann::json ch = {{"name", "x"}, {"sensors", {"a"}}, {"k_um_per_c", {1.0}}, {"intercept_um", 0}};
  expect_field({{"kind", "linear"}, {"ridge_lambda", 0}, {"sensors", {"a"}}, {"channels", {ch, ch}}}, "channels");
  expect_field({{"kind", "linear"},
                {"ridge_lambda", 0},
                {"sensors", {"a", "b"}},
                {"channels", {{{"name", "x"}, {"sensors", {"a", "a"}}, {"k_um_per_c", {1.0, 2.0}}, {"intercept_um", 0}}}}},
               "channels[0].sensors[1]");
}

// The file's wrapper (WriteThermalModelFile): another format or a newer version is refused by field.
TEST(ModelJson, AnotherFormatOrVersionIsRefused) {
  const std::string dir = testing::TempDir("json_format");
  const nlohmann::json model = {{"kind", "linear"},
                                {"ridge_lambda", 0},
                                {"sensors", {"a"}},
                                {"channels", {{{"name", "x"}, {"sensors", {"a"}}, {"k_um_per_c", {1.0}}, {"intercept_um", 0}}}}};
  const auto field_of = [&](const nlohmann::json& doc) -> std::string {
    WriteTextFile(dir + "/m.json", doc.dump());
    try {
      ReadThermalModelFile(dir + "/m.json");
    } catch (const InputError& e) {
      return e.field();
    }
    return "";
  };
  EXPECT_EQ(field_of({{"format", "trueaxis-thermal-model"}, {"version", 1}, {"model", model}}), "");
  EXPECT_EQ(field_of({{"format", "x"}, {"version", 1}, {"model", model}}), "format");
  EXPECT_EQ(field_of({{"format", "trueaxis-thermal-model"}, {"version", 2}, {"model", model}}), "version");
}

TEST(PredictSeries, RefusesASeriesWithoutTheModelsSensor) {
  ThermalSeries s = SelectionFixture(2);
  LinearFitOptions o;
  o.selection.max_sensors = 2;
  LinearThermalModel m = FitLinearModel(s, o);
  ThermalSeries other = s;
  other.temperature_names[static_cast<std::size_t>(*s.TemperatureIndex(m.InputSensors()[0]))] = "renamed";
  try {
    PredictSeries(m, other);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), m.InputSensors()[0]);
  }
}

}  // namespace
}  // namespace trueaxis::thermal

namespace trueaxis::thermal {
namespace {

TEST(Evaluation, ModelsBeatNoCompensationOnHeldOutBlocks) {
  // Four 2 h blocks (0/2000/0/3000 rpm); the heated sensor s0 drives the error.
  const ThermalSeries s = testing::MakeSpindleBlockSeries(6);
  EvaluationOptions eo;
  eo.train_blocks = "0-1";
  eo.validate_blocks = "2-3";
  for (ModelKind k : {ModelKind::kMlr, ModelKind::kRidge, ModelKind::kPsoBp, ModelKind::kHysteresis}) {
    ThermalFitOptions o;
    o.kind = k;
    o.linear.selection.max_sensors = 2;
    o.network.temperature_inputs = 1;
    o.network.particles = 20;
    o.network.pso_iterations = 20;
    o.network.epochs = 50;
    eo.models.push_back(o);
  }
  ThermalEvaluation ev = EvaluateThermalModels(s, {}, eo);
  EXPECT_EQ(ev.train_rows.size(), 960u);
  EXPECT_EQ(ev.validate_rows.size(), 960u);
  EXPECT_FALSE(ev.in_sample);
  ASSERT_EQ(ev.models.size(), 5u);  // + ridge on all sensors, the reference a selection must beat
  EXPECT_EQ(ev.models[0].name, "ridge (all sensors)");
  // 3000 rpm is never seen in training; the linear models extrapolate the
  // linear physics, the network (sigmoid output) cannot go beyond its
  // training range, so it only has to beat doing nothing.
  for (const auto& m : ev.models) {
    const double limit = m.name == "pso-bp" ? 0.8 : 0.1;
    EXPECT_LT(m.validate[0].rmse_um, limit * ev.baseline_validate[0].rmse_um) << m.name;
  }
  // The constant baseline (training mean) is reported beside "no compensation": its residual is
  // the error minus the training mean, so its RMSE is the error's spread about that mean.
  ASSERT_EQ(ev.constant_validate.size(), ev.baseline_validate.size());
  double mean = 0;
  for (auto r : ev.train_rows) mean += s.errors_um(r, 0);
  mean /= static_cast<double>(ev.train_rows.size());
  double ss = 0;
  for (auto r : ev.validate_rows) ss += (s.errors_um(r, 0) - mean) * (s.errors_um(r, 0) - mean);
  EXPECT_NEAR(ev.constant_validate[0].rmse_um, std::sqrt(ss / static_cast<double>(ev.validate_rows.size())), 1e-9);
  EXPECT_NE(ev.BriefReport().find("constant (train mean)"), std::string::npos);
  EXPECT_NE(ev.MarkdownTable().find("% of constant"), std::string::npos);
  // in-sample is flagged
  eo.validate_blocks = "1-2";
  eo.models.resize(1);
  EXPECT_TRUE(EvaluateThermalModels(s, {}, eo).in_sample);
}

}  // namespace
}  // namespace trueaxis::thermal
