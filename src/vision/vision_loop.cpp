// Seed 001 in the loop (include/trueaxis/vision/vision_loop.hpp).
#include "trueaxis/vision/vision_loop.hpp"

#include <cmath>
#include <stdexcept>

#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"
#include "trueaxis/sim/virtual_machine.hpp"
#include "trueaxis/station/installation.hpp"

namespace trueaxis::vision {

VisionLoopResult RunVisionLoop(const MarkerDescription& marker, const CameraModel& camera, const VisionDayOptions& day,
                               const sim::MachineDescription& machine, const VisionLoopOptions& loop,
                               const std::function<void(const VisionFrame&, const cv::Mat&)>& frame_sink) {
  if (!(loop.cycle_s > 0) || loop.cycle_s > day.frame_interval_s)
    throw std::invalid_argument("the compensator cycle must be > 0 and not longer than the frame interval");
  if (loop.term_valid_s < 0) throw std::invalid_argument("term_valid_s must be ≥ 0");
  sim::VirtualMachine vm(machine, day.seed);
  const int zi = machine.AxisIndex(loop.z_axis);  // the machine's axis order is the CNC link's
  if (zi < 0) throw std::invalid_argument("the machine has no axis '" + loop.z_axis + "'");
  const auto z = static_cast<std::size_t>(zi);
  // The machine installation `run` uses, without a model: the camera's Δz is the only term (the
  // temperatures are judged all the same; nothing here computes with them, so no filter).
  station::InstallationConfig installation_config;
  installation_config.source = "vision run";
  installation_config.compensator = loop.compensator;
  installation_config.signal_processing = false;
  station::Installation installation(installation_config, vm, vm, [&vm] { return vm.TimeS(); }, "");
  runtime::Compensator* comp = &installation.compensator();
  const double valid_s = loop.term_valid_s > 0
                             ? loop.term_valid_s
                             : (marker.max_rejected_in_row + 1) * day.frame_interval_s + loop.cycle_s;

  VisionLoopResult out;
  const double z0_um = vm.ErrorUm(z);  // the axis's own error where Z is parked, before the day
  double ss_with = 0, ss_without = 0, last_output_um = 0;
  long cycles = 0;
  const std::uint32_t counted = ~static_cast<std::uint32_t>(runtime::kAlarmNoModel);
  auto advance_to = [&](sim::VirtualSpindle& spindle, double t_s) {
    while (vm.TimeS() < t_s - 1e-9) {
      const double dt = std::min(loop.cycle_s, t_s - vm.TimeS());
      spindle.AdvanceTo(vm.TimeS() + dt);
      vm.SetExtraErrorUm(z, spindle.ZErrorUm());  // the spindle's true growth at the tool
      vm.Advance(dt);
      installation.Cycle(vm.TimeS());
      const auto& s = installation.CommitWrite(runtime::WriteCnc(vm, installation.command()));
      out.alarms_seen |= s.alarms & counted;
      const double with = vm.ErrorUm(z) - z0_um, without = with - vm.CorrectionUm(z);
      ss_with += with * with, ss_without += without * without, ++cycles;
      out.with_max_um = std::max(out.with_max_um, std::abs(with));
      out.without_max_um = std::max(out.without_max_um, std::abs(without));
      out.max_output_step_um = std::max(out.max_output_step_um, std::abs(s.axes[z].output_um - last_output_um));
      last_output_um = s.axes[z].output_um;
    }
  };
  auto sink = [&](const VisionFrame& f, const cv::Mat& img) {
    VisionLoopSample smp;
    smp.time_s = f.time_s;
    smp.z_error_with_um = vm.ErrorUm(z) - z0_um;
    smp.correction_um = vm.CorrectionUm(z);
    smp.z_error_without_um = smp.z_error_with_um - smp.correction_um;
    smp.alarms = comp->LastStatus().alarms & counted;
    smp.feed_hold = vm.FeedHold();
    out.samples.push_back(smp);
    // The Δz in force as the Z term (error sign: a longer spindle moves the tool down, −Δz),
    // renewed by each credible reading; a rejected frame leaves the last one in force until it expires.
    if (f.reading.credible()) comp->SetExtraErrorUm(z, -f.growth_in_force_um, f.time_s + valid_s);
    if (f.stop) {  // seed 001: stop the machine and ask for the marker to be redrawn
      vm.SetFeedHold(true);
      comp->SetVisionStop(true);
      out.feed_hold_at_s = f.time_s;
    }
    if (frame_sink) frame_sink(f, img);
  };
  out.day = RunVisionDay(marker, camera, day, sink, advance_to);
  out.alarm_message = out.day.stop_message;
  if (cycles > 0) out.with_rms_um = std::sqrt(ss_with / cycles), out.without_rms_um = std::sqrt(ss_without / cycles);
  return out;
}

}  // namespace trueaxis::vision
