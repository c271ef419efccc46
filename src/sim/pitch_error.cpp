#include "trueaxis/sim/pitch_error.hpp"

#include <cmath>
#include <random>

namespace trueaxis::sim {


PitchErrorProfile::PitchErrorProfile(const AxisDescription& axis, std::uint64_t serial_seed)
    : travel_mm_(axis.travel_mm), progressive_um_(axis.pitch.progressive_um), curvature_um_(axis.pitch.curvature_um) {
  std::uint64_t axis_hash = 1469598103934665603ull;
  for (char c : axis.name) axis_hash = (axis_hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  std::mt19937_64 rng(serial_seed ^ axis_hash);
  std::uniform_real_distribution<double> u(0, 1);
  const double lead = axis.lead_mm;
  for (std::size_t k = 0; k < axis.pitch.lead_harmonics_um.size(); ++k)
    periodic_.push_back({2 * M_PI * static_cast<double>(k + 1) / lead, axis.pitch.lead_harmonics_um[k], 2 * M_PI * u(rng)});
  auto random_waves = [&](double rms, double lambda, std::vector<Wave>& out) {
    const int n = 8;
    double sum_sq = 0;
    for (int i = 0; i < n; ++i) {
      double wl = lambda * std::exp(std::log(0.4) + (std::log(3.0) - std::log(0.4)) * u(rng));
      double amp = 0.5 + u(rng);
      out.push_back({2 * M_PI / wl, amp, 2 * M_PI * u(rng)});
      sum_sq += amp * amp / 2;
    }
    for (auto& w : out) w.amp_um *= rms / std::sqrt(sum_sq);
  };
  random_waves(axis.pitch.random_um, axis.pitch.random_wavelength_mm, random_);
  random_waves(axis.pitch.flank_difference_um, axis.pitch.random_wavelength_mm * 2, flank_);
}

double PitchErrorProfile::ErrorUm(double x_mm, int direction) const {
  const double s = travel_mm_ > 0 ? x_mm / travel_mm_ : 0;
  double e = progressive_um_ * s + curvature_um_ * 4 * s * (1 - s);
  for (const auto& w : periodic_) e += w.amp_um * std::sin(w.k_rad_per_mm * x_mm + w.phase);
  for (const auto& w : random_) e += w.amp_um * std::sin(w.k_rad_per_mm * x_mm + w.phase);
  if (direction != 0) {
    double f = 0;
    for (const auto& w : flank_) f += w.amp_um * std::sin(w.k_rad_per_mm * x_mm + w.phase);
    e += 0.5 * (direction > 0 ? f : -f);
  }
  return e;
}

}  // namespace trueaxis::sim
