#pragma once
// ISO 230-2 / VDI/DGQ 3441 evaluation of a bidirectional positioning test.
//
// Notation (ISO 230-2): target i, run j, direction ↑ (approach in +, '+' in
// files) and ↓ ('-'); x_ij = deviation (actual − target), here in µm.
// All formulas, with their source, are in docs/analysis.md. In short:
//   x̄_i↑ = mean_j x_ij↑                s_i↑ = sqrt(Σ(x_ij↑ − x̄_i↑)² / (n−1))
//   x̄_i  = (x̄_i↑ + x̄_i↓)/2           B_i  = x̄_i↑ − x̄_i↓
//   R_i↑ = 2k·s_i↑                      R_i  = max(k·s_i↑ + k·s_i↓ + |B_i|, R_i↑, R_i↓)
//   B = max|B_i|, B̄ = mean B_i, R↑ = max R_i↑, R = max R_i
//   E↑ = max x̄_i↑ − min x̄_i↑,  E = max(x̄↑,x̄↓) − min(x̄↑,x̄↓),  M = max x̄_i − min x̄_i
//   A↑ = max(x̄_i↑ + k·s_i↑) − min(x̄_i↑ − k·s_i↑),  A = the same over both directions
// with k = 2 (ISO 230-2:1997/2006/2014) or 3 (1988). VDI/DGQ 3441:
//   Ps_j = 6·(s_j↑ + s_j↓)/2, U_j = |x̄_j↑ − x̄_j↓|, Pa = max x̄_j − min x̄_j,
//   P = max(x̄_j + (U_j + Ps_j)/2) − min(x̄_j − (U_j + Ps_j)/2).
//
// Evaluate() is a pure function of the measurement; it validates first and
// throws InputError (file, line, field) for data it cannot evaluate.
#include <string>
#include <vector>

#include "trueaxis/analysis/standard.hpp"
#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::analysis {

struct EvaluationOptions {
  // Any name FindStandard accepts; see StandardNames().
  std::string standard = "ISO 230-2:2014";

  bool IsValid(std::string* why) const;
};

// Everything about one target position, µm unless named otherwise.
struct TargetResult {
  double target_mm = 0;
  int n_up = 0, n_down = 0;        // runs in each direction
  double mean_up_um = 0;           // x̄_i↑
  double mean_down_um = 0;         // x̄_i↓
  double mean_um = 0;              // x̄_i (bidirectional)
  double s_up_um = 0;              // s_i↑
  double s_down_um = 0;            // s_i↓
  double reversal_um = 0;          // B_i = x̄_i↑ − x̄_i↓ (signed)
  double R_up_um = 0;              // R_i↑ = 2k·s_i↑
  double R_down_um = 0;            // R_i↓
  double R_um = 0;                 // R_i (bidirectional)
  double vdi_scatter_um = 0;       // Ps_j
  double vdi_reversal_span_um = 0; // U_j = |B_i|
};

// Axis values, µm.
struct AxisResult {
  double A_um = 0, A_up_um = 0, A_down_um = 0;
  double B_um = 0, B_mean_um = 0;
  double E_um = 0, E_up_um = 0, E_down_um = 0;
  double M_um = 0;
  double R_um = 0, R_up_um = 0, R_down_um = 0;
  // VDI/DGQ 3441
  double P_um = 0, Pa_um = 0, Ps_max_um = 0, Ps_mean_um = 0, U_max_um = 0, U_mean_um = 0;
};

struct Evaluation {
  Standard standard;
  std::string source;               // the measurement's source (file)
  int runs = 0;                     // distinct run numbers
  std::vector<TargetResult> targets;  // sorted by target_mm
  AxisResult axis;

  // A few lines: standard, targets × runs, A, B, E, M, R (and P for VDI).
  std::string BriefReport() const;
  // BriefReport plus every axis value and the per-target table, aligned.
  std::string FullReport() const;
};

Evaluation Evaluate(const measure::Measurement& m, const EvaluationOptions& options = {});

}  // namespace trueaxis::analysis
