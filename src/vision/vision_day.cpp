// A day of the camera against the virtual spindle (include/trueaxis/vision/vision_day.hpp).
#include "trueaxis/vision/vision_day.hpp"

#include <cmath>
#include <deque>
#include <numeric>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>

#include "trueaxis/vision/credibility.hpp"

namespace trueaxis::vision {

std::vector<std::string> DisturbanceNames() {
  return {"clean", "noise", "blur", "light", "glints", "droplets", "chips", "drift", "wear", "rotation", "all"};
}

bool ApplyDisturbance(const std::string& name, VisionDayOptions& o) {
  auto& d = o.disturbances;
  if (name == "clean") return true;
  if (name == "noise") d.noise_grey = 2.0, d.shot_noise = 0.05;
  else if (name == "blur") d.blur_sigma_px = 1.8;
  else if (name == "light") d.light_gradient = 0.3, o.light_swing = 0.25;
  else if (name == "glints") d.glints = 1;
  else if (name == "droplets") d.droplets = 3;
  else if (name == "chips") d.chips = 2;
  else if (name == "drift") o.mount_drift = 1.0;
  else if (name == "wear") o.wear_per_hour = 0.05;
  else if (name == "rotation") o.trigger_jitter_deg = 20.0;
  else if (name == "all") {
    for (const char* n : {"noise", "blur", "light", "glints", "droplets", "chips", "drift", "wear"}) ApplyDisturbance(n, o);
    d.blur_sigma_px = 1.2;
  } else {
    return false;
  }
  return true;
}

std::pair<double, double> ReferenceK(const std::vector<MarkerReading>& readings) {
  double s1 = 0, s2 = 0;
  int n = 0;
  for (const auto& r : readings)
    if (r.measured()) s1 += r.k1, s2 += r.k2, ++n;
  if (n == 0) throw std::runtime_error("no reference image could be measured");
  return {s1 / n, s2 / n};
}

namespace {
sim::SpindleDescription SpindleFor(const MarkerDescription& marker, const VisionDayOptions& o) {
  sim::SpindleDescription sd = o.spindle;
  sd.diameter_mm = marker.diameter_mm;
  sd.length_mm = marker.spindle_length_mm;
  sd.front_length_mm = std::min(sd.front_length_mm, sd.length_mm);
  sd.standard_temp_c = marker.standard_temp_c;
  return sd;
}
}  // namespace

std::vector<SpindleRelationSample> VirtualRelationReference(const MarkerDescription& marker, const VisionDayOptions& o,
                                                            const sim::SpindleSpeedProgram& program, double hours,
                                                            double interval_s) {
  if (!(hours > 0) || !(interval_s > 0)) throw std::invalid_argument("reference run: hours and interval must be > 0");
  sim::VirtualSpindle spindle(SpindleFor(marker, o), program, marker.standard_temp_c);
  std::vector<SpindleRelationSample> out;
  for (double t = 0; t <= hours * 3600.0 + 1e-9; t += interval_s) {
    spindle.AdvanceTo(t);
    out.push_back({t, marker.spindle_length_mm * 1000.0 * spindle.MarkerStrain(), spindle.Rpm(), spindle.GrowthUm()});
  }
  return out;
}

VisionDayResult RunVisionDay(const MarkerDescription& marker_in, const CameraModel& camera, const VisionDayOptions& o,
                             const std::function<void(const VisionFrame&, const cv::Mat&)>& sink,
                             const std::function<void(sim::VirtualSpindle&, double t_s)>& advance_to) {
  if (!(o.frame_interval_s > 0) || !(o.hours > 0)) throw std::invalid_argument("hours and frame interval must be > 0");
  if (o.average_frames < 1) throw std::invalid_argument("average_frames must be ≥ 1");
  sim::VirtualSpindle spindle(SpindleFor(marker_in, o), o.program, marker_in.standard_temp_c);
  std::optional<SpindleRelationPredictor> relation;
  if (o.relation) relation.emplace(*o.relation);
  double last_marker_um = 0;  // the relation's lags run on through frames without a credible reading
  VirtualCamera cam(camera);
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);

  VisionDayResult out;
  MarkerDescription marker = marker_in;
  {  // reference at the standard temperature: clean frames at three trigger angles
    marker.reference_k1 = marker.reference_k2 = 1.0;
    ImageDisturbances clean;
    std::vector<MarkerReading> ref;
    for (double a : {42.0, 45.0, 48.0}) {
      MarkerScene s;
      s.angle_deg = a;
      ref.push_back(MeasureMarker(cam.RenderMarker(marker, s, clean, o.seed + 17), camera, marker, "reference"));
    }
    std::tie(out.reference_k1, out.reference_k2) = ReferenceK(ref);
    marker.reference_k1 = out.reference_k1;
    marker.reference_k2 = out.reference_k2;
  }
  CredibilityMonitor monitor(marker.max_rejected_in_row);
  ScaleAverager scale_average(o.scale_average_frames);
  const int frames = static_cast<int>(std::floor(o.hours * 3600.0 / o.frame_interval_s)) + 1;
  constexpr double kMountExpansionPerK = 23e-6;  // aluminium bracket
  double ss = 0, ssm = 0, ss_without = 0, ss_with = 0;
  std::deque<double> recent;  // last credible readings, for the averaged Z term
  for (int i = 0; i < frames; ++i) {
    const double t = i * o.frame_interval_s;
    if (advance_to) advance_to(spindle, t);
    else spindle.AdvanceTo(t);
    VisionFrame f;
    f.time_s = t;
    f.rpm = spindle.Rpm();
    f.true_k = spindle.MarkerScale();
    f.true_growth_um = spindle.GrowthUm();
    f.marker_growth_um = marker.spindle_length_mm * 1000.0 * (f.true_k - 1);
    MarkerScene s;
    s.scale = f.true_k;
    // Each trigger shows another pair of lines (the pattern repeats every 90°).
    s.angle_deg = 45.0 + o.trigger_jitter_deg * uni(rng) + 90.0 * (i % 4);
    s.light = 1.0 + o.light_swing * std::sin(2 * std::numbers::pi * t / (o.hours * 3600.0) * 1.7);
    const double mount_dt = o.mount_drift * (spindle.HousingC() - marker.standard_temp_c);
    s.drift_distance_mm = kMountExpansionPerK * o.mount_length_mm * mount_dt;
    s.drift_y_mm = 0.5 * s.drift_distance_mm;
    s.drift_x_mm = 0.3 * s.drift_distance_mm;
    s.wear = std::min(1.0, o.wear_per_hour * t / 3600.0);
    const cv::Mat img = cam.RenderMarker(marker, s, o.disturbances, o.seed * 1000003ull + static_cast<std::uint64_t>(i));
    f.reading = MeasureMarker(img, camera, marker, "frame " + std::to_string(i));
    scale_average.Apply(f.reading, marker);
    f.stop = monitor.Add(f.reading);
    if (f.stop) {  // feed hold: the machine (and its spindle) stops until the marker is redrawn
      out.stop_frame = i;
      out.stop_message = monitor.message();
      spindle.Hold(true);
    }
    out.max_rpm = std::max(out.max_rpm, f.rpm);
    if (f.reading.credible()) last_marker_um = f.reading.growth_um;
    f.growth_um = relation ? relation->Push(t, last_marker_um, f.rpm) : f.reading.growth_um;
    if (f.reading.credible()) {
      recent.push_back(f.growth_um);
      if (static_cast<int>(recent.size()) > o.average_frames) recent.pop_front();
    }
    f.growth_in_force_um = recent.empty() ? 0.0 : std::accumulate(recent.begin(), recent.end(), 0.0) / recent.size();
    const bool bad = !f.reading.measured() || std::abs(f.reading.growth_um - f.marker_growth_um) > o.bad_um;
    if (f.reading.credible()) {
      out.accepted_bad += bad;
      ++out.credible;
      const double e = f.growth_um - f.true_growth_um;
      const double em = f.reading.growth_um - f.marker_growth_um;
      ss += e * e, ssm += em * em;
      out.max_um = std::max(out.max_um, std::abs(e));
      out.max_vs_marker_um = std::max(out.max_vs_marker_um, std::abs(em));
    } else {
      ++out.rejected;
      out.rejected_bad += bad;
    }
    // Z error at the tool (vertical spindle: −Δz); the vision term corrects by the Δz in force.
    const double z_without = -f.true_growth_um;
    const double z_with = -f.true_growth_um + f.growth_in_force_um;
    ss_without += z_without * z_without, ss_with += z_with * z_with;
    if (sink) sink(f, img);
    out.frames.push_back(std::move(f));
  }
  if (out.credible > 0) out.rms_um = std::sqrt(ss / out.credible), out.rms_vs_marker_um = std::sqrt(ssm / out.credible);
  out.z_error_without_rms_um = std::sqrt(ss_without / frames);
  if (o.relation) out.relation_warning = SpindleRelationSpeedWarning(*o.relation, out.max_rpm);
  out.z_error_with_rms_um = std::sqrt(ss_with / frames);
  return out;
}

}  // namespace trueaxis::vision
