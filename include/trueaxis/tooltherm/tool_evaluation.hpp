#pragma once
// Proof of the tool thermal models (docs/tool-thermal.md, "Proof"): fit every
// tool's models on one recorded day, then run a different day (another seed:
// another program, other tool changes) with each model in the loop through
// the tool offset limiter, and score the tip error that remains per tool,
// over the samples where the tool cuts (where the tip makes the part; the
// ramp after a tool change falls in the change and the spindle's run-up).
#include <array>
#include <map>
#include <vector>

#include "trueaxis/tooltherm/tool_day.hpp"
#include "trueaxis/tooltherm/tool_offset.hpp"

namespace trueaxis::tooltherm {

struct ToolScore {
  int tool = 0;
  int samples = 0;  // cutting samples of this tool on the test day
  std::array<double, kToolModelKinds.size()> rms_um{};  // by ToolModelKind
  std::array<double, kToolModelKinds.size()> max_um{};
  // Spread of the true error about the best single Tv line on the test day: the part one
  // curve cannot explain (how large the hysteresis is), µm RMS.
  double curve_spread_um = 0;
};

struct ToolEvaluation {
  std::map<int, ToolErrorModel> models;  // fitted on the training day
  std::vector<ToolScore> tools;          // on the test day
  std::vector<std::string> warnings;
};

// Fewer rows than this on the training day: the tool gets a flagged stand-in (tool_fallback.hpp).
inline constexpr std::size_t kMinToolTrainingRows = 20;

// Bounds of the sensor's factor on the free growth (FitToolModels).
inline constexpr double kMinSensorGrowthFactor = 0.5, kMaxSensorGrowthFactor = 2.0;

// Every tool's models; a tool with too little training gets FallbackModelFromOtherTools (warned).
// The zones models get each zone's free growth (ZoneGrowthUmPerC) times the sensor's factor: the
// median, over the tools with enough rows for their own zone slopes (two or more, else 1), of the
// whole zone slope per µm of free growth — what the readings make of the free growth on this
// machine and sensor (emissivity setting, parts not seen), clamped to [0.5, 2].
std::map<int, ToolErrorModel> FitToolModels(const ToolTable& table, const ToolDayRecording& training,
                                            std::vector<std::string>* warnings);

// Residual tip error (true error + applied correction) of every sample of `test` for one model kind.
std::vector<double> CompensatedResidualUm(const std::map<int, ToolErrorModel>& models, ToolModelKind kind,
                                          const ToolDayRecording& test, const ToolOffsetOptions& options);

ToolEvaluation EvaluateToolModels(const ToolTable& table, const ToolDayRecording& training, const ToolDayRecording& test,
                                  const ToolOffsetOptions& options = {});

}  // namespace trueaxis::tooltherm
