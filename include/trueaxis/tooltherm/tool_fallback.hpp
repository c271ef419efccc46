#pragma once
// A model for a tool that cut too little on its training day (docs/tool-thermal.md,
// "A tool without enough training"): built from the tools that were fitted on the
// same machine and sensor, scaled by the tool's geometry, and flagged.
//
// Each fitted tool i gives its Tv slope b_i (the one curve, µm per °C) per µm of
// free growth of its gauge length, g_i = α_tool·length + α_holder·holder_length
// (µm per °C when tool and holder warm alike); the fallback's slope is the median
// ratio times this tool's g, its intercept the median intercept. The lag and
// two-body forms use that line (the lag with the median τ), so every model kind
// predicts with it. When the other tools have zones models, `best` is a zones model: the
// median of their whole zone slope (Σ b_r) per µm of free growth, spread over this tool's
// zones by each zone's free growth (ZoneGrowthUmPerC), and the median of their zones
// intercepts; else the one curve. `fallback_from_tools` names the
// tools it came from — the model is a stand-in until the tool is measured cutting.
#include <map>

#include "trueaxis/tooltherm/tool_error_model.hpp"
#include "trueaxis/tooltherm/tool_table.hpp"

namespace trueaxis::tooltherm {

// Free growth of the tool's gauge length per °C (µm/°C), from its and its holder's material.
double GaugeGrowthUmPerC(const ToolDescription& tool);

// Fills *out and returns true; false when no tool fitted on its own data (with known materials) exists.
bool FallbackModelFromOtherTools(const ToolDescription& tool, const std::map<int, ToolErrorModel>& fitted,
                                 const ToolTable& table, int training_rows, ToolErrorModel* out);

}  // namespace trueaxis::tooltherm
