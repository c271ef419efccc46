// Held-out check on the virtual machine (the bench's study, small): fit on one
// campaign of the VMC-850's X axis, predict another day's campaign, and
// require the compensated ISO 230-2 A to be a small fraction of the
// uncorrected one — the claim bench/results/modelfit.md makes, as a test.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <gtest/gtest.h>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/sim/campaign.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::model {
namespace {

namespace fs = std::filesystem;

std::vector<FitState> Campaign(std::uint64_t seed, const std::string& dir, bool other_path) {
  const auto machine = sim::ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
  sim::CampaignOptions o;
  o.out_dir = dir;
  o.seed = seed;
  o.axes = {"X"};
  o.laser.runs = 3;
  o.warm_runs = 2;
  o.max_warm_measurements = 6;
  if (other_path) {
    o.nut_step_c = 0.8;
    o.warmup_feed_low_mm_min = 1000;  // a gentler warm-up: another day's path
    o.warmup_feed_high_mm_min = 1500;
    o.ambient_day_offsets = {30, 110};
  }
  fs::remove_all(dir);
  sim::RunCampaign(machine, o);
  return LoadFitStates({}, (fs::path(dir) / "manifest.json").string());
}

TEST(SimHeldOut, FitOnOneDayCompensatesMostOfAnotherDaysError) {
  const fs::path root = fs::temp_directory_path() / ("trueaxis_model_sim_" + std::to_string(::getpid()));
  const auto a = Campaign(1, (root / "A").string(), false);
  const auto b = Campaign(2, (root / "B").string(), true);
  const auto fit = FitCompositeModel(a, {});
  ASSERT_EQ(fit.model.axes.size(), 1u);
  const auto& axis = fit.model.axes[0];
  ASSERT_TRUE(fit.summary.axes[0].thermal_fitted) << fit.summary.FullReport();
  EXPECT_EQ(axis.key_sensors.front(), "x_nut") << fit.summary.FullReport();  // the first key: the axis' own nut
  EXPECT_FALSE(axis.ambient_sensor.empty());
  EXPECT_LT(axis.rho_um_per_mm_per_c, 0);  // the screw grows away from its fixed end
  double sum_u = 0, sum_r = 0;
  for (const auto& st : b) {
    const double a_u = analysis::Evaluate(st.measurement).axis.A_um;
    const double a_r = analysis::Evaluate(PredictionResidual(axis, st.measurement, st.coolant)).axis.A_um;
    EXPECT_LT(a_r, a_u) << st.label;  // never worse than no compensation
    sum_u += a_u;
    sum_r += a_r;
  }
  std::cout << "held-out mean ISO A over " << b.size() << " states: uncorrected " << sum_u / b.size()
            << " µm, residual " << sum_r / b.size() << " µm\n";
  EXPECT_LT(sum_r, 0.4 * sum_u) << "mean A uncorrected " << sum_u / b.size() << " µm, residual " << sum_r / b.size();
  fs::remove_all(root);
}

}  // namespace
}  // namespace trueaxis::model

namespace trueaxis::model {
namespace {

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A re-fit with --add-to-previous and no new file must reproduce the model: the previous fit's
// temperature log (thermal lag history) travels with its sources (it was lost: τ changed).
TEST(SimCampaignLog, RefitFromPreviousSourcesKeepsTheTemperatureLogAndTheLag) {
  const fs::path root = fs::temp_directory_path() / ("trueaxis_model_log_" + std::to_string(::getpid()));
  const auto a = Campaign(3, (root / "A").string(), false);
  ASSERT_FALSE(a.empty());
  EXPECT_FALSE(a.back().temperature_log.empty());
  EXPECT_FALSE(a.back().history.time_s.empty());
  const auto first = FitCompositeModel(a, {});
  WriteModelFile(first.model, (root / "m.json").string());
  const auto again = LoadPreviousSources(ReadModelFile((root / "m.json").string()), (root / "m.json").string());
  ASSERT_EQ(again.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(again[i].history.time_s.size(), a[i].history.time_s.size());
  const auto second = FitCompositeModel(again, {});
  EXPECT_EQ(second.model.axes[0].key_lag_s, first.model.axes[0].key_lag_s);
  EXPECT_EQ(second.model.axes[0].key_sensors, first.model.axes[0].key_sensors);
  fs::remove_all(root);
}

// The campaign log is checked row by row and against the measurement it is used for.
TEST(SimCampaignLog, CutRowsAndAnotherCampaignsLogAreRefused) {
  const fs::path root = fs::temp_directory_path() / ("trueaxis_model_badlog_" + std::to_string(::getpid()));
  Campaign(4, (root / "A").string(), false);
  Campaign(5, (root / "B").string(), true);
  const auto file = root / "A" / "X_04_warm_03.csv";
  ASSERT_TRUE(fs::exists(file));
  const auto m = measure::ReadMeasurementCsv(file.string());
  const double start = std::stod(*m.Meta("campaign_time_s"));
  EXPECT_NO_THROW(TemperatureHistoryFromLog((root / "A/temperature_log.csv").string(), m, start));
  // Another campaign's log (other seed, other day path): its readings at that time disagree.
  try {
    TemperatureHistoryFromLog((root / "B/temperature_log.csv").string(), m, start);
    ADD_FAILURE() << "another campaign's log was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another campaign"), std::string::npos) << e.what();
    // It names the log's row nearest the measurement's start: that line's time_s is within a step.
    std::istringstream lines(ReadAll(root / "B/temperature_log.csv"));
    std::string l, header;
    int n = 0;
    while (std::getline(lines, l) && ++n < e.line())
      if (header.empty() && !l.empty() && l[0] != '#') header = l;
    ASSERT_GT(e.line(), 1) << e.what();
    ASSERT_EQ(header.rfind("time_s,", 0), 0u) << header;
    EXPECT_NEAR(std::stod(l.substr(0, l.find(','))), start, 120) << l;
  }
  // A row cut to 5 fields.
  std::string log = ReadAll(root / "A/temperature_log.csv");
  const auto third_line = log.find('\n', log.find('\n', log.find('\n') + 1) + 1);
  std::string cut = log.substr(0, third_line + 1);
  const auto next = log.substr(third_line + 1, log.find('\n', third_line + 1) - third_line - 1);
  std::string five;
  int commas = 0;
  for (char c : next) {
    if (c == ',' && ++commas == 5) break;
    five += c;
  }
  std::ofstream(root / "cut.csv") << cut << five << "\n";
  try {
    TemperatureHistoryFromLog((root / "cut.csv").string(), m, start);
    ADD_FAILURE() << "a row cut short was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("5 fields"), std::string::npos) << e.what();
  }
  // A log that ends before the measurement starts (cut at its first lines).
  std::ofstream(root / "short.csv") << cut;
  EXPECT_THROW(TemperatureHistoryFromLog((root / "short.csv").string(), m, start), InputError);
  fs::remove_all(root);
}

}  // namespace
}  // namespace trueaxis::model
