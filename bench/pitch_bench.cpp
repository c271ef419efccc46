// Following error of the pitch correction vs feed, applied ahead of the motion
// (seed 002) or one interpolation interval late, on the virtual VMC-850's X
// axis with the once-per-lead table (and a lead/4 table) from a fine
// calibration; plus the cost of one interpolation cycle.
//   ./build/bench/bench_pitch --benchmark_min_time=0.05
// Counters: following_max_um / following_rms_um = |applied − exact correction|
// over a 300 mm move; position_max_um = |actual − commanded| during it (truth).
#include <benchmark/benchmark.h>

#include "trueaxis/pitch/fine_cycle.hpp"
#include "trueaxis/pitch/proof.hpp"

namespace {

using namespace trueaxis;

const sim::MachineDescription& Vmc850() {
  static const auto m = sim::ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
  return m;
}

const pitch::PitchErrorTable& Table(int samples_per_lead) {
  static const measure::Measurement fine = [] {
    pitch::FineSessionOptions so;
    return pitch::RunFineSession(Vmc850(), 0, so).measurement;
  }();
  static pitch::PitchErrorTable tables[2];
  auto& t = tables[samples_per_lead == 1 ? 0 : 1];
  if (t.size() == 0) {
    pitch::TableFromMeasurementOptions o;
    o.samples_per_lead = samples_per_lead;
    t = pitch::TableFromMeasurement(fine, o);
  }
  return t;
}

// Args: feed mm/min, mode (0 ahead, 1 late), cycle µs, samples per lead.
void BM_FollowingError(benchmark::State& state) {
  const double feed = static_cast<double>(state.range(0));
  sim::InterpolatorOptions io;
  io.cycle_s = static_cast<double>(state.range(2)) * 1e-6;
  const auto& table = Table(static_cast<int>(state.range(3)));
  const auto mode = state.range(1) == 0 ? sim::FeedForward::kAhead : sim::FeedForward::kLate;
  pitch::FollowingPoint fp;
  for (auto _ : state) {
    fp = pitch::FollowingErrorVsFeed(Vmc850(), 0, table, {feed}, io, 1).front();
    benchmark::DoNotOptimize(fp);
  }
  const sim::MoveStats& s = mode == sim::FeedForward::kAhead ? fp.ahead : fp.late;
  state.counters["following_max_um"] = s.max_abs_following_um;
  state.counters["following_rms_um"] = s.rms_following_um;
  state.counters["position_max_um"] = s.max_abs_position_error_um;
  state.SetLabel(mode == sim::FeedForward::kAhead ? "ahead" : "late");
}
BENCHMARK(BM_FollowingError)
    ->ArgsProduct({{1000, 5000, 10000, 20000, 40000}, {0, 1}, {1000, 4000}, {1, 4}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Cost of one interpolation cycle with the table (4 fine steps of the virtual machine included).
void BM_InterpolatorCycle(benchmark::State& state) {
  sim::VirtualMachine vm(Vmc850(), 1);
  const auto& table = Table(1);
  sim::CncInterpolator ipo(vm, 0, {}, [&table](double x, int dir) { return pitch::CorrectionUm(table, x, dir); });
  std::size_t cycles = 0;
  double target = 800;
  for (auto _ : state) {
    cycles += ipo.MoveTo(target, 10000).cycles;
    target = target > 400 ? 20 : 800;
  }
  state.counters["ns_per_cycle"] = benchmark::Counter(static_cast<double>(cycles) * 1e-9,
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_InterpolatorCycle)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
