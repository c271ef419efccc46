#pragma once
// A day of the seed-001 camera against the virtual spindle (docs/vision.md):
// the spindle runs its speed program; every frame_interval_s a frame is
// triggered (spindle angle 45° ± jitter, so two lines face the camera; each
// trigger shows another pair of lines), rendered by the virtual camera with the
// chosen disturbances, measured, passed through the stop rule; the Δz in force
// (last credible reading) is the additional Z term. Truth is recorded beside.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "trueaxis/sim/spindle.hpp"
#include "trueaxis/vision/camera_model.hpp"
#include "trueaxis/vision/marker.hpp"
#include "trueaxis/vision/marker_measurement.hpp"
#include "trueaxis/vision/spindle_relation.hpp"
#include "trueaxis/vision/virtual_camera.hpp"

namespace trueaxis::vision {

struct VisionDayOptions {
  double hours = 10.0;
  double frame_interval_s = 300.0;
  double trigger_jitter_deg = 3.0;  // trigger angle 45° ± this (uniform)
  ImageDisturbances disturbances;
  double light_swing = 0.0;         // relative day/night swing of the light level
  double mount_drift = 0.0;         // 1 = the camera bracket (aluminium) grows with the housing temperature
  double mount_length_mm = 100.0;
  double wear_per_hour = 0.0;       // marker wear grows by this per hour (1 = worn away)
  std::uint64_t seed = 1;
  int average_frames = 1;           // the Z term is the mean of the last N credible readings
  int scale_average_frames = 12;    // with a reference scale: mean of its last N readings
  double bad_um = 5.0;              // a reading off by more than this (vs Czb·(K_true − 1)) is "bad"
  sim::SpindleSpeedProgram program = sim::SpindleSpeedProgram::HeatingCoolingDay(10.0);
  sim::SpindleDescription spindle;  // its diameter and length are set from the marker file
  // Given: every credible reading goes through the calibrated marker-to-spindle relation (with the
  // spindle's speed) instead of the seed's Czb·(K − 1) alone (spindle_relation.hpp).
  std::optional<SpindleRelation> relation;
};

// Named disturbance sets: clean, noise, blur, light, glints, droplets, chips, drift, wear, rotation, all.
std::vector<std::string> DisturbanceNames();
// Applies one named set to options; false when the name is unknown.
bool ApplyDisturbance(const std::string& name, VisionDayOptions& options);

struct VisionFrame {
  double time_s = 0, rpm = 0;
  double true_k = 1, true_growth_um = 0;  // marker scale and the spindle's real Δz
  double marker_growth_um = 0;            // Czb·(K_true − 1): what a perfect reading would give
  MarkerReading reading;
  double growth_um = 0;                   // this frame's Δz: the reading's, or through the relation (credible frames)
  double growth_in_force_um = 0;          // the Z term the compensator gets (mean of the last credible readings)
  bool stop = false;                      // the stop rule tripped at this frame (the spindle is held from here on)
};

struct VisionDayResult {
  std::vector<VisionFrame> frames;
  double reference_k1 = 1, reference_k2 = 1;  // raw K at the standard temperature (t = 0)
  int stop_frame = -1;
  std::string stop_message;
  // Statistics over credible frames: reading − truth (µm).
  double rms_um = 0, max_um = 0;
  double rms_vs_marker_um = 0, max_vs_marker_um = 0;  // reading − Czb·(K_true − 1): the camera's part
  int credible = 0, rejected = 0;
  int rejected_bad = 0;   // rejected frames that were bad (unmeasurable or off by > bad_um): correct rejections
  int accepted_bad = 0;   // credible frames off by > bad_um: what the ε test let through
  double z_error_without_rms_um = 0, z_error_with_rms_um = 0;  // Z error at the tool without / with the vision term
  double max_rpm = 0;               // the highest speed of the day
  std::string relation_warning;     // the relation was used beyond its calibrated speeds (empty: not)
};

// A virtual reference run for the relation: the spindle's real growth and the marker's perfect
// reading Czb·(K_true − 1) every interval_s over `hours` of `program` (what a displacement probe
// and the camera give on a calibration day).
std::vector<SpindleRelationSample> VirtualRelationReference(const MarkerDescription& marker, const VisionDayOptions& options,
                                                            const sim::SpindleSpeedProgram& program, double hours,
                                                            double interval_s);

// frame_sink, if given, receives each rendered frame (e.g. to write PNGs). advance_to, if given,
// moves the spindle (and whatever runs beside it: the virtual machine and its compensator,
// vision_loop.hpp) to the next frame time; by default the spindle alone is advanced.
VisionDayResult RunVisionDay(const MarkerDescription& marker, const CameraModel& camera, const VisionDayOptions& options,
                             const std::function<void(const VisionFrame&, const cv::Mat&)>& frame_sink = nullptr,
                             const std::function<void(sim::VirtualSpindle&, double t_s)>& advance_to = nullptr);

// Raw K1, K2 read at the standard temperature from a few clean renders at
// trigger angles (what `vision reference` does with a user's images).
std::pair<double, double> ReferenceK(const std::vector<MarkerReading>& readings_at_standard);

}  // namespace trueaxis::vision
