// Seed-001 vision: cost per frame (render, measure) at the supported
// resolutions, and the precision of ring centres and edges on renders with a
// random sub-pixel position, clean and under each disturbance (counters).
// Results: bench/results/vision.md.
#include <cmath>
#include <map>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "trueaxis/vision/marker_measurement.hpp"
#include "trueaxis/vision/virtual_camera.hpp"
#include "trueaxis/vision/vision_day.hpp"

namespace {
using namespace trueaxis::vision;

// The same 110 mm field at 250 mm on sensors of 640, 1280 and 2048 px width.
CameraModel Camera(int width) { return CameraModel::ForField(width, width * 3 / 4, 110, 250, -0.05); }

const VirtualCamera& Cam(int width) {
  static std::map<int, std::unique_ptr<VirtualCamera>> cams;
  auto& c = cams[width];
  if (!c) c = std::make_unique<VirtualCamera>(Camera(width));
  return *c;
}

void BM_RenderMarker(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0));
  const auto& cam = Cam(w);
  MarkerDescription m;
  MarkerScene s;
  ImageDisturbances d;
  d.noise_grey = 2;
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(cam.RenderMarker(m, s, d, seed++));
  state.SetLabel(std::to_string(w) + "x" + std::to_string(w * 3 / 4));
}
BENCHMARK(BM_RenderMarker)->Arg(640)->Arg(1280)->Arg(2048)->Unit(benchmark::kMillisecond);

void BM_MeasureMarker(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0));
  MarkerDescription m;
  m.ink_width_mm = 1.0;
  MarkerScene s;
  ImageDisturbances d;
  d.noise_grey = 2;
  const cv::Mat img = Cam(w).RenderMarker(m, s, d, 1);
  const CameraModel cam = Camera(w);
  for (auto _ : state) benchmark::DoNotOptimize(MeasureMarker(img, cam, m, "bench"));
  state.SetLabel(std::to_string(w) + "x" + std::to_string(w * 3 / 4));
}
BENCHMARK(BM_MeasureMarker)->Arg(640)->Arg(1280)->Arg(2048)->Unit(benchmark::kMillisecond);

// Precision: 24 frames, each at a random sub-pixel position (axis height and
// sideways), angle 45° ± 4°, strain 0…3e-4; ring centre error against the exact
// projection (px), single-stroke and single-edge scatter (px), Δz error (µm).
void BM_Precision(benchmark::State& state) {
  const auto names = DisturbanceNames();
  const std::string name = names[static_cast<std::size_t>(state.range(0))];
  const int w = static_cast<int>(state.range(1));
  VisionDayOptions o;
  ApplyDisturbance(name, o);
  const CameraModel cam = Camera(w);
  MarkerDescription m;
  {  // reference at the standard temperature
    std::vector<MarkerReading> ref;
    for (double a : {42.0, 45.0, 48.0}) {
      MarkerScene s;
      s.angle_deg = a;
      ref.push_back(MeasureMarker(Cam(w).RenderMarker(m, s, {}, 3), cam, m, "ref"));
    }
    std::tie(m.reference_k1, m.reference_k2) = ReferenceK(ref);
  }
  double ss_ring = 0, max_ring = 0, ss_stroke = 0, ss_edge = 0, ss_dz = 0, max_dz = 0, ss_k2 = 0;
  int n_ring = 0, n = 0, credible = 0, frames = 0;
  for (auto _ : state) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1), strain(0, 3e-4);
    for (int i = 0; i < 24; ++i) {
      MarkerScene s;
      s.scale = 1 + strain(rng);
      s.angle_deg = 45 + 4 * u(rng) + 90 * i;
      s.drift_y_mm = 0.3 * u(rng);  // ±1.7 px at 640
      s.drift_x_mm = 0.3 * u(rng);
      s.wear = std::min(1.0, o.wear_per_hour * 5);  // half a day of wear
      s.drift_distance_mm = o.mount_drift * 23e-6 * 100 * 8;  // bracket 8 °C warm
      s.light = 1 - 0.5 * o.light_swing * (1 + u(rng));
      if (o.trigger_jitter_deg > 5) s.angle_deg = 45 + o.trigger_jitter_deg * u(rng) + 90 * i;
      const auto r = MeasureMarker(Cam(w).RenderMarker(m, s, o.disturbances, 1000 + i), cam, m, "p");
      ++frames;
      if (!r.measured()) continue;
      // Exact ring heights at the front of the ring (px from the principal point), in the
      // units the measurement reports (undistorted, height / (1 − r)).
      const double D = std::hypot(m.distance_mm + s.drift_distance_mm, s.drift_x_mm);
      const double r_true = 0.5 * m.diameter_mm * s.scale / D;
      for (int k = 0; k < 2; ++k) {
        const double y = s.drift_y_mm + (k == 0 ? -0.5 : 0.5) * m.circle_spacing_mm * s.scale;
        const double truth_px = y / D / (1 - r_true) * cam.fy;
        // Both readings are in the same units; the measurement used r0·K1 for r.
        const double e = r.ring_height_px[k] - truth_px;
        ss_ring += e * e, max_ring = std::max(max_ring, std::abs(e)), ++n_ring;
      }
      ss_stroke += r.stroke_rms_px * r.stroke_rms_px;
      ss_edge += r.edge_rms_px * r.edge_rms_px;
      ++n;
      if (r.credible()) {
        ++credible;
        const double e = r.growth_um - 300e3 * (s.scale - 1);
        ss_dz += e * e, max_dz = std::max(max_dz, std::abs(e));
        ss_k2 += (r.k2 - s.scale) * (r.k2 - s.scale);
      }
    }
  }
  state.SetLabel(name + " @" + std::to_string(w));
  state.counters["ring_centre_rms_px"] = n_ring ? std::sqrt(ss_ring / n_ring) : NAN;
  state.counters["ring_centre_max_px"] = max_ring;
  state.counters["stroke_rms_px"] = n ? std::sqrt(ss_stroke / n) : NAN;
  state.counters["edge_rms_px"] = n ? std::sqrt(ss_edge / n) : NAN;
  state.counters["dz_rms_um"] = credible ? std::sqrt(ss_dz / credible) : NAN;
  state.counters["dz_max_um"] = max_dz;
  state.counters["k2_rms_ppm"] = credible ? 1e6 * std::sqrt(ss_k2 / credible) : NAN;
  state.counters["credible_pct"] = frames ? 100.0 * credible / frames : 0;
}
BENCHMARK(BM_Precision)
    ->ArgsProduct({benchmark::CreateDenseRange(0, 10, 1), {640}})
    ->Args({0, 1280})
    ->Args({0, 2048})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
