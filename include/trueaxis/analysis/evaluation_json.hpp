#pragma once
// JSON views of analysis results, the contract of `trueaxis analyze --json`
// (docs/analysis.md): axis values in µm under A_um, A_up_um, A_down_um, B_um,
// B_mean_um, E_um, E_up_um, E_down_um, M_um, R_um, R_up_um, R_down_um (ISO),
// P_um, Pa_um, Ps_max_um, Ps_mean_um, U_max_um, U_mean_um (VDI), plus
// standard, coverage_factor, positions, runs, source and per_target[].
#include <nlohmann/json.hpp>

#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/analysis/evaluation.hpp"

namespace trueaxis::analysis {

nlohmann::json AxisResultToJson(const AxisResult& a);
nlohmann::json EvaluationToJson(const Evaluation& ev);
nlohmann::json DecompositionToJson(const Decomposition& d);
// {"after": <axis values>, "change_um": after − before per key, "source": ...}
nlohmann::json ComparisonToJson(const Evaluation& before, const Evaluation& after);

}  // namespace trueaxis::analysis
