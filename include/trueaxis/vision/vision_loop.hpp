#pragma once
// Seed 001 in the loop (docs/vision.md, "In the loop"): the day of the camera
// (vision_day.hpp) drives a runtime::Compensator that runs against an
// in-process sim::VirtualMachine.
//
//   virtual spindle ─► true growth ─► VirtualMachine::SetExtraErrorUm(Z, −Δz_true)
//   frame ─► MeasureMarker ─► credible Δz ─► Compensator::SetExtraErrorUm(Z, −Δz, valid until)
//   Compensator cycle (every cycle_s) ─► output shaper ─► WriteCompensation ─► the machine's Z
//   stop rule (> 5 non-credible in a row) ─► VirtualMachine::SetFeedHold(true),
//                                            Compensator::SetVisionStop(true) (alarm vision_stop)
//
// The Z error at the tool is read from the machine (actual − commanded on Z),
// so it is what the compensator really wrote through its limiter. No model is
// published: the Z correction is the vision term alone (alarm no_model is
// therefore always raised and not counted).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/vision/vision_day.hpp"

namespace trueaxis::vision {

struct VisionLoopOptions {
  std::string z_axis = "Z";         // the machine axis the spindle grows along
  double cycle_s = 1.0;             // compensator cycle (the virtual machine's controller interval)
  // How long a Δz reading stays in force (loop time). 0 = until the stop rule could trip:
  // (max_rejected_in_row + 1) frame intervals + one cycle. Past it the term is dropped (stale_input).
  double term_valid_s = 0;
  runtime::CompensatorOptions compensator;  // its shaper bounds and ramps the vision term
};

struct VisionLoopSample {  // one per frame, taken before the frame's reading is applied
  double time_s = 0;
  double z_error_with_um = 0;     // machine's Z error at the tool with the compensator's output
  double z_error_without_um = 0;  // the same without it (error − correction applied)
  double correction_um = 0;       // the compensator's Z output the machine holds
  std::uint32_t alarms = 0;       // compensator alarms of the last cycle
  bool feed_hold = false;
};

struct VisionLoopResult {
  VisionDayResult day;
  std::vector<VisionLoopSample> samples;
  // Over every compensator cycle (not just frames): RMS and worst |Z error at the tool| (µm),
  // as the change from t = 0 (the axis's own error at its parked position is not the spindle's).
  double with_rms_um = 0, with_max_um = 0, without_rms_um = 0, without_max_um = 0;
  double max_output_step_um = 0;  // largest change of the Z output in one cycle
  std::uint32_t alarms_seen = 0;  // union over the day (no_model left out)
  double feed_hold_at_s = -1;     // when the stop rule put the machine in feed hold (−1: never)
  std::string alarm_message;      // the stop rule's message to the user
};

// Throws std::invalid_argument when the machine has no such axis or the options are invalid.
VisionLoopResult RunVisionLoop(const MarkerDescription& marker, const CameraModel& camera, const VisionDayOptions& day,
                               const sim::MachineDescription& machine, const VisionLoopOptions& loop,
                               const std::function<void(const VisionFrame&, const cv::Mat&)>& frame_sink = nullptr);

}  // namespace trueaxis::vision
