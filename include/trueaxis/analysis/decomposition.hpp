#pragma once
// Decomposition of the positioning error of a ball-screw axis (seed 002):
//
//   δ(x) = δ_f(x) + δ_p(x) + ψ
//   δ_f  progressive (cumulative) error: low-order polynomial trend, a + b·x (+ …)
//   δ_p  periodic error: Σ_h A_h·sin(2π·h·x/L + φ_h), harmonics of the screw lead L
//   ψ    random error, summarised by σ and drawn as the band δ_f + δ_p ± 3σ
//
// δ_f and δ_p are fitted jointly by linear least squares to the bidirectional
// mean deviations x̄_i of an Evaluation (systematic part); σ is the pooled
// run-to-run standard deviation (the s_i↑, s_i↓ of ISO 230-2), i.e. the part
// that no deterministic compensation can remove.
//
// Aliasing: harmonic h has period L/h. It can only be fitted when the targets
// sample it at better than two points per period, i.e. every gap between
// neighbouring targets is below L/(2h). Harmonics that fail this are NOT
// fitted; the result says so (resolved = false, with the reason) rather than
// reporting an amplitude that the data cannot support.
#include <string>
#include <vector>

#include "trueaxis/analysis/evaluation.hpp"

namespace trueaxis::analysis {

struct DecompositionOptions {
  double lead_mm = 0;        // screw lead L; 0 = unknown (no periodic part is fitted)
  int trend_degree = 1;      // progressive part: polynomial degree 0..3 (seed 002: a + b·x)
  int harmonics = 2;         // highest harmonic order N of the lead to try
  double band_sigmas = 3;    // half-width of the random band in σ

  bool IsValid(std::string* why) const;
};

struct Harmonic {
  int order = 1;             // h
  double period_mm = 0;      // L / h
  bool resolved = false;     // fitted (false: aliased or under-determined)
  double amplitude_um = 0;   // A_h (0 when not resolved)
  double phase_rad = 0;      // φ_h in A_h·sin(2π·h·x/L + φ_h)
  std::string note;          // why it was not fitted, when resolved = false
};

struct DecompositionPoint {
  double target_mm = 0;
  double mean_um = 0;        // x̄_i, what was fitted
  double progressive_um = 0; // δ_f(x_i)
  double periodic_um = 0;    // δ_p(x_i)
  double residual_um = 0;    // x̄_i − δ_f − δ_p (systematic part the model does not explain)
};

struct Decomposition {
  DecompositionOptions options;
  std::vector<double> trend_coefficients;  // µm, µm/mm, µm/mm², … (about the first target)
  double trend_origin_mm = 0;              // x of the polynomial's origin
  std::vector<Harmonic> harmonics;
  std::vector<DecompositionPoint> points;
  double sigma_um = 0;                     // pooled random σ
  double residual_rms_um = 0;              // RMS of residual_um
  double min_gap_mm = 0, max_gap_mm = 0;   // target spacing
  std::vector<std::string> notes;          // plain-language caveats (aliasing, missing lead, …)

  bool periodic_fitted() const;
  double Progressive(double x_mm) const;
  double Periodic(double x_mm) const;
  double Systematic(double x_mm) const { return Progressive(x_mm) + Periodic(x_mm); }

  std::string BriefReport() const;
  std::string FullReport() const;
};

// Throws std::invalid_argument for invalid options.
Decomposition Decompose(const Evaluation& ev, const DecompositionOptions& options);

}  // namespace trueaxis::analysis
