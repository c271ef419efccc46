#pragma once
// The measurement data model: one laser-interferometer positioning test of
// one axis, i.e. bidirectional runs over a set of target positions, with the
// temperatures recorded alongside (docs/formats.md).
//
// Sign convention (docs/sign-convention.md): deviation_um is the measured
// actual position minus the target position, in micrometres.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/direction.hpp"

namespace trueaxis::measure {

struct MeasurementPoint {
  int run = 1;  // 1-based run (cycle) number
  Direction direction = Direction::kForward;  // direction of approach
  double target_mm = 0;
  double deviation_um = 0;                 // actual - target
  std::optional<double> time_s;            // seconds since the start of the test
  std::vector<double> temperatures_c;      // parallel to Measurement::sensor_names; NaN = not read
  int source_line = 0;                     // line in the file it came from (0 if none)
};

struct Measurement {
  std::string source;  // file path or other origin, used in error messages
  // "# key: value" metadata in file order (axis, machine, date, operator, cte_um_per_m_c, ...).
  std::vector<std::pair<std::string, std::string>> metadata;
  // The file line each metadata key was read from (absent or 0: not from a line, e.g. set by the
  // simulator). Kept by SetMeta; read with MetaLine for error messages. Keyed by name, so it stays
  // right when `metadata` is reordered or edited.
  std::map<std::string, int> metadata_lines;
  std::vector<std::string> sensor_names;  // "nut" for column t_nut_c
  bool has_time = false;
  std::vector<MeasurementPoint> points;

  // Metadata lookup by key (case-sensitive); nullopt when absent.
  std::optional<std::string> Meta(const std::string& key) const;
  // The file line of a metadata entry, for error messages; 0 when absent or not read from a line.
  int MetaLine(const std::string& key) const;
  void SetMeta(const std::string& key, const std::string& value, int line = 0);
  // Index of a sensor in sensor_names, or nullopt.
  std::optional<std::size_t> SensorIndex(const std::string& name) const;

  // Sorted distinct targets (targets closer than 1 nm are the same target).
  std::vector<double> Targets() const;
  // Sorted distinct run numbers.
  std::vector<int> Runs() const;
};

// Whether the test ran with the machine's error compensation active, from its '# compensation:'
// line: on / yes / true → true, off / no / false / none → false (case-insensitive), no such line →
// nullopt (unknown: a laser file from elsewhere seldom says). Any other value throws InputError
// naming the source and the field. Such a file's deviations already include a correction: fitting
// a model on them, or subtracting a prediction from them, counts the model twice.
std::optional<bool> CompensationActive(const Measurement& m);

// A warning when the deviations look like another unit than µm: every |deviation| under 0.2 µm
// over a run longer than 50 mm — no working axis is that true; deviations in mm (or a file
// labelled nm holding mm) read that way. nullopt otherwise. The text names the largest value.
std::optional<std::string> DeviationUnitWarning(const Measurement& m);

// Checks what an ISO 230-2 evaluation needs and throws InputError naming the
// source, the line and the field otherwise: no points; fewer than 2 runs; a
// duplicate (run, direction, target); a target measured in one direction only.
void ValidateForEvaluation(const Measurement& m);

}  // namespace trueaxis::measure
