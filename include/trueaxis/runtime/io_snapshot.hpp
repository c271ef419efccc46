#pragma once
// What the I/O phases hand the step, and what the step hands back to them
// (docs/runtime.md, *One cycle* and *Timing contract*).
//
//   TemperatureSnapshot  ← signal::JudgedTemperatureSource::Read at the temperature rate (1–10 Hz):
//                          judged values only (the temperature judge ran before the step)
//   CncSnapshot          ← CncLink::Read every cycle (+ the result of the last write)
//   CncCommand           → CncLink::WriteCompensation
//
// Every snapshot carries the time it was taken and a sequence number, so the
// step can tell a new value from one it has already seen and judge its age.
// The functions below are the I/O phases themselves: they touch the hardware
// and may block (a socket timeout); they run on an I/O worker or, for an
// in-process plant, inline before and after the step — never inside it.
#include <cstdint>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/signal/judged_temperature.hpp"

namespace trueaxis::runtime {

struct TemperatureSnapshot {
  std::uint64_t sequence = 0;  // 0: nothing read yet
  double sampled_at_s = 0;     // loop time of the read
  bool ok = false;             // the source answered (else `channels` are not this read's)
  // The judge's verdict per channel (signal::TemperatureMonitor): the step applies no
  // per-value rule of its own, only this snapshot's age and the hold time.
  std::vector<signal::JudgedTemperature> channels;

  explicit TemperatureSnapshot(std::size_t channel_count = 0) : channels(channel_count) {}
};

struct CncSnapshot {
  std::uint64_t sequence = 0;  // 0: nothing read yet
  double sampled_at_s = 0;
  bool read_ok = false;
  std::vector<hw::AxisState> axes;
  hw::CncState machine;
  // Asynchronous I/O only: the last command the CNC worker tried to write, whether
  // that failed, and the last command the CNC accepted — so the step ramps on from
  // exactly what the CNC holds.
  std::uint64_t attempted_sequence = 0;
  bool write_failed = false;
  std::uint64_t written_sequence = 0;

  explicit CncSnapshot(std::size_t axis_count = 0) : axes(axis_count) {}
};

struct CncCommand {
  std::uint64_t sequence = 0;  // 0: nothing to write yet
  std::vector<double> correction_um;  // per axis, CNC units, correction sign

  explicit CncCommand(std::size_t axis_count = 0) : correction_um(axis_count, 0.0) {}
};

// The I/O phases. No allocation (the snapshots are sized by their constructors).
// `sequence` numbers the reads of one producer (1, 2, ...).
// A raw hw::TemperatureSource does not fit here: it goes through the judge first
// (signal::MonitoredTemperatureSource).
inline void ReadTemperatures(signal::JudgedTemperatureSource& source, double now_s, std::uint64_t sequence,
                             TemperatureSnapshot& out) {
  out.ok = source.Read(out.channels);
  out.sampled_at_s = now_s;
  out.sequence = sequence;
}
inline void ReadCnc(hw::CncLink& link, double now_s, std::uint64_t sequence, CncSnapshot& out) {
  out.read_ok = link.Read(out.axes, out.machine);
  out.sampled_at_s = now_s;
  out.sequence = sequence;
}
// Writes `command`. Returns the link's answer.
inline bool WriteCnc(hw::CncLink& link, const CncCommand& command) { return link.WriteCompensation(command.correction_um); }

}  // namespace trueaxis::runtime
