// Held-out check on the virtual machine (the bench's study, small): fit on one
// campaign of the VMC-850's X axis, predict another day's campaign, and
// require the compensated ISO 230-2 A to be a small fraction of the
// uncorrected one — the claim bench/results/modelfit.md makes, as a test.
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/model/fit_input.hpp"
#include "trueaxis/model/model_fit.hpp"
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
    o.warmup_feed_low_mm_min = 2500;
    o.warmup_feed_high_mm_min = 3500;
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
