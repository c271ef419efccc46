// Held-out proof of the automatic composite-model fit on the virtual machine
// (issue 4): two calibration campaigns of the VMC-850 example machine on
// different days (other seed: noise, homing, weather, laser; other ambient
// days; another warm-up path), fit on campaign A, predict every measurement
// of campaign B, and report per held-out state the ISO 230-2 A of the
// uncorrected error beside the A of (measured − predicted).
//
// Then Google Benchmark timings of the fit itself and of one prediction.
//   ./build/bench/bench_modelfit [--markdown] [--benchmark_min_time=0.2s]
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/sim/campaign.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace {
namespace fs = std::filesystem;
using namespace trueaxis;

struct Campaigns {
  std::vector<model::FitState> a, b;
};

std::vector<model::FitState> RunOne(const sim::MachineDescription& machine, const sim::CampaignOptions& o) {
  fs::remove_all(o.out_dir);
  sim::RunCampaign(machine, o);
  return model::LoadFitStates({}, (fs::path(o.out_dir) / "manifest.json").string());
}

const Campaigns& GetCampaigns() {
  static Campaigns c = [] {
    const auto machine = sim::ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
    const fs::path root = fs::temp_directory_path() / "trueaxis_modelfit_bench";
    sim::CampaignOptions a;
    a.out_dir = (root / "A").string();
    a.seed = 1;
    sim::CampaignOptions b = a;  // the other day
    b.out_dir = (root / "B").string();
    b.seed = 2;
    b.ambient_day_offsets = {30, 110};     // other seasons / weather
    b.nut_step_c = 0.8;                    // another warm-up path: fewer, larger steps ...
    b.warmup_feed_low_mm_min = 2500;       // ... at other feeds
    b.warmup_feed_high_mm_min = 3500;
    b.max_warm_measurements = 8;
    b.max_coolant_measurements = 3;
    Campaigns c;
    c.a = RunOne(machine, a);
    c.b = RunOne(machine, b);
    return c;
  }();
  return c;
}

double IsoA(const measure::Measurement& m) { return analysis::Evaluate(m).axis.A_um; }

// The seed's "均值处理": every point carries its file's mean temperatures instead of its own.
measure::Measurement WithMeanTemperatures(measure::Measurement m) {
  const std::size_t n = m.sensor_names.size();
  std::vector<double> sum(n, 0);
  std::vector<int> cnt(n, 0);
  for (const auto& p : m.points)
    for (std::size_t i = 0; i < n && i < p.temperatures_c.size(); ++i)
      if (std::isfinite(p.temperatures_c[i])) sum[i] += p.temperatures_c[i], ++cnt[i];
  for (auto& p : m.points)
    for (std::size_t i = 0; i < n && i < p.temperatures_c.size(); ++i) p.temperatures_c[i] = cnt[i] ? sum[i] / cnt[i] : NAN;
  return m;
}

void HeldOutStudy(bool markdown) {
  const auto& c = GetCampaigns();
  struct Variant {
    const char* name;
    model::FitOptions o;
  };
  // The first three without the thermal lag (key_lag_grid_s = {0}: the static model as before
  // the lag existed); the fourth is the default fit (auto, τ chosen by LOSO CV).
  std::vector<Variant> variants(4);
  for (auto& v : variants) v.o.key_lag_grid_s = {0};
  variants[0].name = "polynomial";
  variants[0].o.geometric = model::FitOptions::Geometric::kPolynomial;
  variants[1].name = "table";
  variants[1].o.geometric = model::FitOptions::Geometric::kTable;
  variants[2].name = "auto";
  variants[2].o.geometric = model::FitOptions::Geometric::kAuto;
  variants[3].name = "auto + lag (default)";
  variants[3].o = model::FitOptions{};
  std::vector<model::FitResult> fits;
  for (auto& v : variants) fits.push_back(model::FitCompositeModel(c.a, v.o));
  // Fourth: auto, fitted and predicted with each file's mean temperatures.
  std::vector<model::FitState> a_mean = c.a;
  for (auto& st : a_mean) st.measurement = WithMeanTemperatures(st.measurement);
  model::FitOptions mean_opts;
  mean_opts.key_lag_grid_s = {0};
  const auto fit_mean = model::FitCompositeModel(a_mean, mean_opts);

  for (std::size_t ai = 0; ai < fits[0].model.axes.size(); ++ai) {
    const auto& axis_name = fits[0].model.axes[ai].axis;
    std::cout << fmt::format("\n### Axis {} — fitted on campaign A ({} files), predicted on campaign B\n\n", axis_name,
                             c.a.size());
    for (std::size_t vi = 0; vi < fits.size(); ++vi) {
      const auto& s = fits[vi].summary.axes[ai];
      const auto& a = fits[vi].model.axes[ai];
      std::cout << fmt::format("- {} [{} | {}]: keys {}, Px {:.1f} mm, ρ {:.5f} µm/mm/°C, thermal LOSO CV {:.2f} µm "
                               "(without: {:.2f} µm), geometric CV {:.2f}/{:.2f} µm (+/−)\n",
                               variants[vi].name, s.directions[0].choice, s.directions[1].choice,
                               fmt::join(a.key_sensors, "+"), a.reference_position_mm,
                               a.rho_um_per_mm_per_c, s.thermal_cv_rms_um, s.no_thermal_cv_rms_um,
                               s.directions[0].geometric_cv_rms_um, s.directions[1].geometric_cv_rms_um);
      if (!s.lag_reason.empty()) {
        std::cout << fmt::format("  - lag: {}; grid", s.lag_reason);
        for (const auto& lc : s.lag_candidates) std::cout << fmt::format(" τ {:.0f} s → {:.2f} µm;", lc[0], lc[1]);
        std::cout << "\n";
      }
    }
    std::cout << "\n| held-out state (B) | coolant | nut rise °C | ambient Δ °C | A uncorrected µm | A residual poly µm "
                 "| A residual table µm | A residual auto µm | A residual auto + lag µm | A residual auto, state-mean temps µm | max(R↑,R↓) µm |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    double sum_u = 0, sum_p = 0, sum_t = 0, sum_t2 = 0, sum_l = 0, sum_m = 0;
    int n = 0;
    for (const auto& st : c.b) {
      if (st.axis != axis_name) continue;
      const auto& m = st.measurement;
      const auto ev = analysis::Evaluate(m);
      const double a_p = IsoA(model::PredictionResidual(fits[0].model.axes[ai], m, st.coolant));
      const double a_t = IsoA(model::PredictionResidual(fits[1].model.axes[ai], m, st.coolant));
      const double a_t2 = IsoA(model::PredictionResidual(fits[2].model.axes[ai], m, st.coolant));
      // The lag runs through the logged history before the measurement, as the runtime's would.
      const double a_l = IsoA(model::PredictionResidual(fits[3].model.axes[ai], m, st.coolant, &st.history));
      const double a_m = IsoA(model::PredictionResidual(fit_mean.model.axes[ai], WithMeanTemperatures(m), st.coolant));
      const auto t = model::TemperaturesForPoint(fits[0].model.axes[ai], m, m.points.front());
      const double amb_delta = std::isnan(t.ambient_c) ? NAN : t.ambient_c - fits[0].model.axes[ai].ambient_baseline_c;
      std::cout << fmt::format("| {} | {} | {} | {:.2f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} |\n", st.label,
                               CoolantStateName(st.coolant), m.Meta("nut_rise_c").value_or("?"), amb_delta,
                               ev.axis.A_um, a_p, a_t, a_t2, a_l, a_m, std::max(ev.axis.R_up_um, ev.axis.R_down_um));
      sum_u += ev.axis.A_um, sum_p += a_p, sum_t += a_t, sum_t2 += a_t2, sum_l += a_l, sum_m += a_m, ++n;
    }
    if (n)
      std::cout << fmt::format("| **mean of {} states** | | | | **{:.1f}** | **{:.1f}** | **{:.1f}** | **{:.1f}** | **{:.1f}** | **{:.1f}** | |\n",
                               n, sum_u / n, sum_p / n, sum_t / n, sum_t2 / n, sum_l / n, sum_m / n);
    const auto& sm = fit_mean.summary.axes[ai];
    std::cout << fmt::format("\nstate-mean variant: keys {}, thermal LOSO CV {:.2f} µm\n",
                             fmt::join(fit_mean.model.axes[ai].key_sensors, "+"), sm.thermal_cv_rms_um);
  }
  (void)markdown;
}

void BM_FitCampaign(benchmark::State& state) {
  const auto& c = GetCampaigns();
  for (auto _ : state) {
    auto r = model::FitCompositeModel(c.a, {});
    benchmark::DoNotOptimize(r);
  }
  state.SetLabel(fmt::format("{} files", c.a.size()));
}
BENCHMARK(BM_FitCampaign)->Unit(benchmark::kMillisecond);

void BM_PredictOnePoint(benchmark::State& state) {
  static const auto fit = model::FitCompositeModel(GetCampaigns().a, {});
  const auto& axis = fit.model.axes[0];
  std::vector<double> temps(axis.key_sensors.size(), 22.0);
  model::ThermalState ts{temps, 21.0, CoolantState::kFlood, true};
  double x = 0;
  for (auto _ : state) {
    x = x > 800 ? 0 : x + 0.37;
    benchmark::DoNotOptimize(model::Predict(axis, x, Direction::kReverse, ts));
  }
}
BENCHMARK(BM_PredictOnePoint);

}  // namespace

int main(int argc, char** argv) {
  bool markdown = false;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--markdown") == 0) markdown = true;
  HeldOutStudy(markdown);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
