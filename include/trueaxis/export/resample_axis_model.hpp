#pragma once
// Resampling a model behind model::AxisErrorModel — a data-driven thermal model
// (`trueaxis thermal fit`: MLR/ridge, PSO-BP, hysteresis) deployed on an axis
// through thermal::ThermalAxisModel — onto a controller table's grid, with its
// temperatures frozen at the values the user gives (docs/export.md, section
// "Data-driven thermal models"). export/ sees only the interface: the caller
// (the CLI) builds the adapter, so export does not depend on thermal/.
//
// Values: correction = −ErrorUm(x, direction, sensors, coolant, dynamics)
// (docs/sign-convention.md) at every grid position and both directions, with
// the model's dynamics at start-up (ResetDynamics, never advanced): a lagged
// input takes its sensor's given temperature as settled, a hysteresis model
// predicts with its start-up (all-data) model. The whole prediction goes into
// the values (options.thermal_in_table is not used: such a model has no
// controller-side temperature line).
//
// Refused (InputError on the option): no --range (the model knows no position
// range of its own), a sensor the model reads without --temp, a --temp the
// model does not read (both name the sensor and list what the model reads).
// Reference point: options.reference_position_mm, else the range's minimum.
#include <string>

#include "trueaxis/export/resample.hpp"
#include "trueaxis/model/axis_error_model.hpp"

namespace trueaxis::exporter {

// Where the model is valid along the axis, when it knows (a network that takes the position: the
// positions it was trained on); NaN: it does not, and the --range given is trusted.
struct AxisModelValidity {
  double min_mm = ResampleOptions::kNaN;
  double max_mm = ResampleOptions::kNaN;
};

// `source` names the model file in error messages and in the table's provenance. A --range or
// grid beyond `validity` is refused like any extrapolation (InputError on --range / the grid option).
ResampleResult ResampleAxisErrorModel(const model::AxisErrorModel& model, const ResampleOptions& options,
                                      const std::string& source, const AxisModelValidity& validity = {});

// True when every value of both curves is the same (within 1 nm): a model that
// does not use the axis position gives one offset over the whole range.
bool IsConstantAlongAxis(const CompensationTable& table);

}  // namespace trueaxis::exporter
