#pragma once
// Compensator: seed 000's 实时补偿模块 + 动态调整模块 for every axis of one
// machine. It owns the installation (options, per-axis interface, channel
// names), the model exchange, the step's state and its buffers, and runs the
// pure step (cycle_step.hpp) on the latest I/O snapshots:
//
//   I/O phase: read temperatures ─► TemperatureSnapshot (with its time; judged values only, from a
//              signal::JudgedTemperatureSource — the temperature judge in front)
//   I/O phase: read the CNC      ─► CncSnapshot         (with its time)
//   Cycle():   pick up a published model, Step(model, state, inputs) ─► command + status
//   I/O phase: write the command; CommitWrite(write_ok)
//
// RunCycle() runs the three phases inline (in-process plants, tests);
// LoopRunner runs the I/O phases on workers with their own rates for real
// hardware, so the cycle never waits on a socket (docs/runtime.md).
//
// Real-time contract: Cycle/CommitWrite/RunCycle allocate nothing, take no
// lock, and free nothing (models are retired through ModelExchange). All
// buffers are sized in the constructor. Exactly one thread calls them;
// PublishModel, SetEnabled, SetAxisEnabled, CollectRetired may be called from
// any other.
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/bound_model.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/runtime/io_snapshot.hpp"
#include "trueaxis/runtime/model_exchange.hpp"

namespace trueaxis::runtime {

// The models a Compensator takes: composites only, or also models behind the generic interface
// (model::AxisErrorModel, e.g. data-driven thermal models). A compensator for composites only does
// not hold the generic models' dynamic state (ModelDynamics::generic, ≈ 7.8 kB an axis) — what a
// workshop server running thousands of composite-model machines saves.
enum class ModelKinds { kCompositeAndGeneric, kCompositeOnly };

class Compensator {
 public:
  // `axes` in the CNC link's axis order; `channel_names` in the source's order.
  // Throws std::invalid_argument on invalid options.
  Compensator(CompensatorOptions options, std::vector<AxisInterface> axes, std::vector<std::string> channel_names,
              ModelKinds kinds = ModelKinds::kCompositeAndGeneric);
  // Convenience: axis order and channel names taken from the link and source;
  // `interfaces` matched by axis name (missing axes get defaults).
  static std::unique_ptr<Compensator> ForHardware(const CompensatorOptions& options, const hw::CncLink& link,
                                                  const signal::JudgedTemperatureSource& source,
                                                  const std::vector<AxisInterface>& interfaces,
                                                  ModelKinds kinds = ModelKinds::kCompositeAndGeneric);

  // ---- any thread except the real-time one ----
  // Binds and publishes; the loop picks it up at its next cycle and ramps to
  // the new correction. Throws InputError (label names the model) on a bad binding.
  void PublishModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label);
  // The same for models behind the generic interface (e.g. data-driven thermal models through
  // their adapter), one per axis; axes without one ramp to zero (alarm no_model_for_axis).
  // Throws std::logic_error on a compensator for composites only (ModelKinds::kCompositeOnly).
  void PublishAxisModels(std::vector<std::shared_ptr<const model::AxisErrorModel>> models, const std::string& label);
  void CollectRetired() { exchange_.CollectRetired(); }
  void SetEnabled(bool on) { enabled_.store(on, std::memory_order_relaxed); }
  void SetAxisEnabled(std::size_t axis, bool on) { axis_enabled_[axis].store(on, std::memory_order_relaxed); }
  bool Enabled() const { return enabled_.load(std::memory_order_relaxed); }
  // An additional error on one axis measured outside the model (µm, error sign; e.g. the camera's
  // spindle Δz on Z, seed 001), added to the model's error before the output shaper
  // (StepInputs::extra_error_um). It is used up to loop time `valid_until_s` (the supplier's own
  // freshness limit, on the Cycle clock); past it the term is dropped (the correction ramps back to
  // the model's) and stale_input is raised until it is renewed or cleared. NaN clears it.
  void SetExtraErrorUm(std::size_t axis, double error_um, double valid_until_s) {
    extra_valid_until_s_[axis].store(valid_until_s, std::memory_order_relaxed);
    extra_error_um_[axis].store(error_um, std::memory_order_relaxed);
  }
  void ClearExtraError(std::size_t axis) { SetExtraErrorUm(axis, std::numeric_limits<double>::quiet_NaN(), 0); }
  // Seed 001's stop rule from outside (the camera): raises the vision_stop alarm while set.
  void SetVisionStop(bool on) { vision_stop_.store(on, std::memory_order_relaxed); }

  const CompensatorOptions& options() const { return options_; }
  ModelKinds kinds() const { return kinds_; }
  const std::vector<AxisInterface>& axes() const { return axes_; }
  const std::vector<std::string>& channel_names() const { return channel_names_; }
  // Snapshot/command shapes for the I/O phases of this installation.
  TemperatureSnapshot MakeTemperatureSnapshot() const { return TemperatureSnapshot(channel_names_.size()); }
  CncSnapshot MakeCncSnapshot() const { return CncSnapshot(axes_.size()); }

  // ---- the real-time thread ----
  // The step on the latest snapshots at time `now_s` (monotonic seconds: wall clock or simulated;
  // the snapshots' times are on the same clock). No I/O. Then write command() and CommitWrite()
  // (inline write) or hand it to the CNC worker and AwaitWrite() (acknowledged by a later snapshot).
  const CycleStatus& Cycle(const TemperatureSnapshot& temperatures, const CncSnapshot& cnc, double now_s);
  const CncCommand& command() const { return out_.command; }
  const CycleStatus& CommitWrite(bool write_ok);
  const CycleStatus& AwaitWrite();
  // The three phases inline: read both, Cycle, write, commit.
  const CycleStatus& RunCycle(hw::CncLink& link, signal::JudgedTemperatureSource& source, double now_s);
  const CycleStatus& LastStatus() const { return out_.status; }
  // Per axis status and per channel status of the last cycle (what a status page shows).
  const StepOutputs& LastOutputs() const { return out_; }
  // Pick-up without a jump: after the start and after every failed CNC read, the first good CNC
  // snapshot that reports what the CNC applies now (hw::AxisState::applied_um) seeds the output
  // shaper there — once two successive snapshots agree on it (a terminal may show an accepted
  // write a scan late) — so the ramp continues from the CNC's value. True until then (a
  // caller that writes only when it may, like the workshop server, waits for it); a CNC that does
  // not report its applied value is taken up from the shaper's own state.
  bool PickUpPending() const { return pickup_pending_; }
  const StepState& state() const { return state_; }

 private:
  StepModel Model() const { return StepModel{options_, axes_, current_, shaping_}; }

  CompensatorOptions options_;
  std::vector<AxisInterface> axes_;
  std::vector<ShaperLimits> shaping_;  // per axis, from options_ and axes_ (fixed for the compensator's life)
  std::vector<std::string> channel_names_;
  ModelKinds kinds_;
  ModelExchange<BoundModel> exchange_;
  std::atomic<std::uint64_t> next_model_id_{1};
  std::atomic<bool> enabled_{true};
  std::unique_ptr<std::atomic<bool>[]> axis_enabled_;
  std::unique_ptr<std::atomic<double>[]> extra_error_um_;        // NaN = none
  std::unique_ptr<std::atomic<double>[]> extra_valid_until_s_;
  std::atomic<bool> vision_stop_{false};

  // RT-thread state and buffers, sized in the constructor.
  const BoundModel* current_ = nullptr;
  StepState state_;
  StepOutputs out_;
  std::vector<std::uint8_t> axis_enabled_now_;
  std::vector<double> extra_error_now_um_;
  bool pickup_pending_ = true;
  std::uint64_t pickup_sequence_ = 0;      // the CNC snapshot last looked at for the pick-up
  std::vector<double> pickup_applied_um_;  // its applied values (NaN: none yet)
  void PickUp(const CncSnapshot& cnc);
  // RunCycle's inline I/O.
  TemperatureSnapshot inline_temperatures_;
  CncSnapshot inline_cnc_;
  std::uint64_t inline_sequence_ = 0;
};

}  // namespace trueaxis::runtime
