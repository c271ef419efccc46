// Cost of the temperature signal chain per channel per sample (the work the
// real-time cycle does for every sensor), and of the conversions.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "trueaxis/signal/channel_filter.hpp"
#include "trueaxis/signal/conversions.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace {
using namespace trueaxis;
using namespace trueaxis::signal;

std::vector<double> NoisySamples(std::size_t n) {
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0, 0.15);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = 24.0 + noise(rng) + (u(rng) < 0.02 ? 5.0 : 0.0);
  return v;
}

void BM_ChannelFilter(benchmark::State& state) {
  FilterOptions o;
  o.hampel_window = static_cast<int>(state.range(0));
  ChannelFilter f(o);
  const auto samples = NoisySamples(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    auto out = f.Process(samples[i++ & 4095], 0.01);
    benchmark::DoNotOptimize(out);
  }
  state.SetLabel("per channel per sample");
}
BENCHMARK(BM_ChannelFilter)->Arg(5)->Arg(9)->Arg(21);

// Whole monitor: calibration, filter, all fault rules, 2 neighbour groups.
// Reported time is per Update() of all channels; the counter gives ns per channel.
void BM_TemperatureMonitorUpdate(benchmark::State& state) {
  const auto channels = static_cast<std::size_t>(state.range(0));
  std::vector<std::string> names;
  for (std::size_t c = 0; c < channels; ++c) names.push_back("t" + std::to_string(c));
  MonitorOptions o;
  o.neighbour_groups = {{"t0", "t1", "t2"}};
  TemperatureMonitor mon(names, o);
  const auto samples = NoisySamples(4096);
  std::vector<hw::RawTemperature> raw(channels);
  double t = 0;
  std::size_t i = 0;
  for (auto _ : state) {
    for (std::size_t c = 0; c < channels; ++c) raw[c] = {samples[(i + 37 * c) & 4095] + c, false};
    mon.Update(t, raw);
    t += 0.01;
    ++i;
    benchmark::DoNotOptimize(mon.reading(0));
  }
  state.counters["ns_per_channel"] = benchmark::Counter(
      static_cast<double>(state.iterations() * channels), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TemperatureMonitorUpdate)->Arg(4)->Arg(16)->Arg(64);

void BM_ConvertAdcCount(benchmark::State& state) {
  const AnalogChannelOptions o;
  int count = 0;
  for (auto _ : state) {
    auto r = ConvertAdcCount(count, o);
    benchmark::DoNotOptimize(r);
    count = (count + 7) & 4095;
  }
}
BENCHMARK(BM_ConvertAdcCount);

}  // namespace

BENCHMARK_MAIN();
