#pragma once
// A virtual working day of tools on the virtual spindle (docs/tool-thermal.md,
// "Virtual day"): a drawn program of operations (tool, speed, cutting power,
// coolant, cut/air-move rhythm) with tool changes and spindle stops; every
// tool of the table lives its own thermal life (in the spindle or in the
// magazine); the mounted one is seen by the virtual thermal camera (or the
// pyrometers) every sample_s, giving Tv by the seed's formula beside the true
// tip error. Same seed, same day.
#include <cstdint>
#include <vector>

#include "trueaxis/sim/spindle.hpp"
#include "trueaxis/tooltherm/thermal_camera.hpp"
#include "trueaxis/tooltherm/tool_error_model.hpp"
#include "trueaxis/tooltherm/tool_table.hpp"

namespace trueaxis::tooltherm {

enum class TvSensor { kCamera, kPyrometer };

// kMixed: a job shop — operations of 4–30 min (cut 20–180 s, air 5–40 s) and stops of 3–40 min.
// kBlocks: long heating and cooling, the course seed 001 describes — each tool cuts for
// 40–90 min (cuts of 5–10 min), then the spindle stops for 30–90 min with the tool in it.
enum class ToolDayProgramKind { kMixed, kBlocks };


struct ToolOperation {
  double start_s = 0, end_s = 0;
  int tool = 0;
  double rpm = 0;        // 0: a stop (the tool stays in the spindle and cools)
  double power_w = 0;    // cutting power while cutting
  bool coolant = false;
  double cut_s = 60, air_s = 15;  // rhythm: cut, air move, cut, …
};

struct ToolDayOptions {
  double hours = 8;
  double sample_s = 2;
  double step_s = 0.5;  // simulation step (≤ sample_s)
  std::uint64_t seed = 1;
  ToolDayProgramKind program = ToolDayProgramKind::kMixed;
  TvSensor sensor = TvSensor::kCamera;
  ThermalCameraOptions camera;
  double ambient_c = 20;
  double ambient_swing_c = 2;   // daily swing (sine over 24 h, peak mid-afternoon)
  double coolant_c = 22;
  sim::SpindleDescription spindle;
};


// Operations of a day: tools in random order (each change an 8 s stop), speed from a cutting speed for the tool's
// material and diameter, power ∝ diameter, coolant half the time, stops of 3–40 min.
std::vector<ToolOperation> DrawToolDayProgram(const ToolTable& table, double hours, std::uint64_t seed,
                                              ToolDayProgramKind kind = ToolDayProgramKind::kMixed);

// count random tools (lengths, diameters, materials, holders) not in any file.
ToolTable RandomToolTable(int count, std::uint64_t seed);

struct ToolDaySample {
  double time_s = 0;
  int tool = 0;
  double tv_c = 0;
  double true_error_um = 0;
  bool restart = false;  // first sample of this mounting
  double rpm = 0;
  bool cutting = false, coolant = false;
  std::vector<double> zone_c;  // Tr per zone of the mounted tool
};

struct ToolDayRecording {
  std::vector<ToolOperation> program;
  std::vector<ToolDaySample> samples;
};

ToolDayRecording RunToolDay(const ToolTable& table, const ToolDayOptions& options);

// The rows of one tool (its mountings, restart at each) for fitting / prediction.
std::vector<ToolRecord> ToolRecordsOf(const ToolDayRecording& day, int tool);

}  // namespace trueaxis::tooltherm
