#pragma once
// The machine log: what a data logger beside a real machine writes every few seconds — the
// clock, the coolant, each axis's position and the path it has travelled (the CNC's distance
// counter), and every temperature channel (empty when the hardware flags it). The calibration
// campaign writes it as temperature_log.csv (the fit reads the thermal history before each laser
// test from it, and the motion history for a model's motion-heat input); the demo writes the
// working day's as day/machine_log.csv. Columns: time_s, date, coolant, <axis>_mm …,
// <axis>_travel_mm …, t_<sensor>_c … (docs/campaign.md).
#include <string>

#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

std::string MachineLogHeader(const VirtualMachine& vm);  // ends with '\n'
std::string MachineLogRow(const VirtualMachine& vm);     // ends with '\n'

}  // namespace trueaxis::sim
