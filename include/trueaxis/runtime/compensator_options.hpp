#pragma once
// Options of the real-time compensator (docs/runtime.md). Ceres-like: every
// field has a safe default; IsValid() explains what is wrong.
#include <map>
#include <string>

#include "trueaxis/runtime/output_shaper.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::runtime {

// What to do once a key sensor has been faulty for longer than the hold time.
enum class SensorFallback {
  kGeometricOnly,  // drop the thermal part (and the ambient part): correction = −Er(x)
  kZero,           // ramp the whole correction of the affected axis to zero
};

// What to do while the CNC link cannot be read.
enum class LinkLossPolicy {
  kHold,        // keep the last value written (the CNC keeps applying it)
  kRampToZero,  // ramp towards zero; takes effect on the writes that still get through
};

// The run config's defaults for the temperature judge's per-value rules ([sensor_fault]
// min_valid_c = -20, max_valid_c = 120, max_rate_c_per_s = 2.0, rate_allowance_c = 0.5; the other
// rules at signal::FaultOptions' defaults).
signal::FaultOptions DefaultJudgeLimits();

struct SensorFaultPolicy {
  // The per-value rules (range, rate of change, stuck, disagreement), applied once, by the
  // temperature judge in front of the step (signal::TemperatureMonitor, built from these by
  // whoever wires the machine); the step itself judges no value. [sensor_fault] min_valid_c,
  // max_valid_c, max_rate_c_per_s (0: no rate rule), rate_allowance_c and [signal]
  // max_disagreement_c are read into this.
  signal::FaultOptions judge = DefaultJudgeLimits();
  // A channel the judge faults keeps its last good value this long, then counts as lost.
  double hold_last_good_s = 60;
  // A temperature snapshot older than this (the temperature worker is stuck on a
  // dead terminal) is treated as a failed read: channels are held, then lost. (The judge's own
  // judge.stale_after_s is about its source failing reads; this is about the snapshot's age.)
  double stale_after_s = 5;
  SensorFallback fallback = SensorFallback::kGeometricOnly;
  // A fallback model taking over (AxisModel::fallbacks) starts from the model's last thermal
  // correction: their difference at the loss is carried and decays with this time constant (s),
  // so the correction does not step to a model that was the worse one a moment ago. 0: the
  // fallback's own prediction at once (the shaper's ramp only). docs/runtime.md, step 4.
  double fallback_handover_s = 7200;

  bool IsValid(std::string* why) const;
};

struct CompensatorOptions {
  OutputShaperOptions shaper;
  SensorFaultPolicy sensor;
  LinkLossPolicy link_loss = LinkLossPolicy::kHold;
  // After a link loss, this many consecutive good reads before the
  // correction follows the model again (from where the CNC was left, ramped).
  int link_recovery_cycles = 3;
  // A CNC snapshot older than this (the CNC worker is stuck on a socket) is a
  // link loss, handled by `link_loss` through the limiter. With I/O workers the
  // loop period must be at most half of it (LoopRunner checks).
  double link_stale_after_s = 0.25;
  // Ramp to zero while the CNC reports its compensation input disabled, so
  // that enabling it on the CNC never applies a stale value at once.
  bool follow_cnc_enable = true;
  // Take the servo direction only while the CNC reports the axis moving (a
  // commanded motion). At standstill the compensation output itself moves the
  // motor by a few µm and a CNC reports that as a direction; following it would
  // flip between the forward and reverse models (a limit cycle of the reversal
  // value). Set false for a CNC that never reports `moving`. A programmed
  // direction the CNC link gives (hw::AxisState::programmed_direction) is
  // taken always.
  bool direction_only_while_moving = true;
  // Without a programmed or moving direction the position decides: a position back from the
  // turning point (the farthest reached in the held direction since the model last switched) by
  // more than this (µm, in the model's frame; above the position noise peak to peak, a few encoder
  // counts), beyond what the compensation itself changed since, is a reversal — however few reads
  // saw the move (docs/runtime.md step 4).
  double direction_min_move_um = 2.0;
  // Model sensor name → temperature channel name (absent: same name).
  std::map<std::string, std::string> channel_map;

  bool IsValid(std::string* why) const;
};

}  // namespace trueaxis::runtime
