#pragma once
// The compensation bound an axis needs, derived from its fitted model (issue 10: a fixed ±100 µm
// clamped a big machine's correction silently). The bound must let the model's own corrections
// through over the travel and the temperatures it may meet, with headroom, and must stay within
// what the controller's compensation input accepts. Pure; no I/O.
//
// Envelope searched: every Er(x) position of both directions (a 201-point grid over the fitted
// range, or the table's points), the key sensors all at the low end or all at the high end of their
// fitted ranges (AxisModel::key_fitted_range_c; the hot end extended by `extra_rise_c`; the sensors
// of one drive warm and cool together),
// the ambient at its baseline ± `ambient_margin_c`, every coolant state with fitted gains; the same
// for each of the axis's fallback models (AxisModel::fallbacks), which drive the axis when a key
// sensor is lost.
//   bound = clamp(round_up(max |correction| × (1 + margin_fraction), round_to_um),
//                 min_bound_um, controller_limit_um)
// When the model needs more than the controller accepts, `limited_by_controller` says so: the
// compensator will then saturate (alarm) where the model asks for more.
#include <string>

#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::model {

struct CompensationBoundOptions {
  double extra_rise_c = 5.0;          // key sensors this much hotter than the hottest fitted reading
  double ambient_margin_c = 5.0;      // ambient this much either side of the fitted baseline
  double margin_fraction = 0.25;      // headroom on the largest correction of the envelope
  double round_to_um = 5.0;
  double min_bound_um = 10.0;
  double controller_limit_um = 1000.0;  // what the CNC's compensation input accepts (physical µm)

  bool IsValid(std::string* why) const;
};

struct CompensationBound {
  double bound_um = 0;          // for runtime::AxisInterface::max_correction_um
  double model_max_um = 0;      // largest |correction| over the envelope
  bool limited_by_controller = false;
  std::string BriefReport() const;  // "±85 µm (model needs up to 66.9 µm + 25 %)"
};

CompensationBound DeriveCompensationBound(const AxisModel& axis, const CompensationBoundOptions& options = {});

}  // namespace trueaxis::model
