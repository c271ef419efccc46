#include "trueaxis/runtime/io_snapshot.hpp"

namespace trueaxis::runtime {

void ReadTemperatures(hw::TemperatureSource& source, double now_s, std::uint64_t sequence, TemperatureSnapshot& out) {
  out.ok = source.Read(out.channels);
  out.sampled_at_s = now_s;
  out.sequence = sequence;
}

void ReadCnc(hw::CncLink& link, double now_s, std::uint64_t sequence, CncSnapshot& out) {
  out.read_ok = link.Read(out.axes, out.machine);
  out.sampled_at_s = now_s;
  out.sequence = sequence;
}

bool WriteCnc(hw::CncLink& link, const CncCommand& command) { return link.WriteCompensation(command.correction_um); }

}  // namespace trueaxis::runtime
