#pragma once
// A thermal-drift recording of the virtual machine, as a real machine would give one for the
// data-driven thermal models (docs/thermal-models.md): its sensors logged every interval_s while
// the machine works a day's programme, beside the TRUE error of each axis at a fixed position
// (what a laser, a touch probe or capacitive sensors against an artefact would measure).
//
// The programme is drawn from the seed, so another seed is another day: phases of 20 min to 3 h
// of machining (every axis reciprocating over the middle 80 % of its travel at a drawn feed and
// duty, dry or with flood coolant) and idling, from the machine's state at the start (cold, for a
// fresh machine) to the end.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

struct ThermalRecordingOptions {
  double hours = 24;
  double interval_s = 60;
  double position_fraction = 0.75;  // where on each axis' travel the error is taken (0..1)
  std::uint64_t programme_seed = 1;

  bool IsValid(std::string* why) const;
};

struct ThermalRecording {
  std::vector<double> time_s;
  std::vector<CoolantState> coolant;
  std::vector<std::string> sensor_names;  // the machine's sensors
  Eigen::MatrixXd temperatures_c;         // rows x sensors, as the sensors read (NaN on a hardware fault)
  std::vector<std::string> error_names;   // "x_at_450mm"
  Eigen::MatrixXd errors_um;              // rows x axes: true error (actual − commanded), direction +
  std::vector<std::string> programme;     // one line per phase, for the file's metadata
};

// Runs `vm` (fresh, at time 0) through the drawn programme and logs it.
ThermalRecording RecordThermalDay(VirtualMachine& vm, const ThermalRecordingOptions& options);

}  // namespace trueaxis::sim
