#pragma once
// A thermal drift recording (docs/thermal-series.md): per sample the time,
// the temperatures of many sensors, one or more measured error channels
// (displacements in µm) and optionally the operating state (spindle speed,
// coolant) and the axis position the error was measured at.
//
// Storage is column-oriented with Eigen matrices (rows = samples) because
// every consumer (selection, regression, networks) works on whole columns.
// NaN marks a missing reading; CleanSeries (series_cleaning.hpp) decides what
// happens to it before any model sees the data.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "trueaxis/core/coolant.hpp"

namespace trueaxis::thermal {

struct ThermalSeries {
  std::string source;                          // file path or origin, used in error messages
  std::map<std::string, std::string> metadata;  // "# key: value" lines
  bool has_time = false;        // false: samples are only ordered (e.g. a position table)
  std::vector<double> time_s;   // seconds; row index when !has_time
  std::vector<int> source_line;  // file line of each row (0 when not from a file)

  std::vector<std::string> temperature_names;  // "t1" for column t1_C / t_t1_c
  Eigen::MatrixXd temperatures_c;              // rows x temperature_names.size()
  std::vector<std::string> error_names;        // "ch1" for column ch1_um / e_ch1_um
  Eigen::MatrixXd errors_um;                   // rows x error_names.size()

  bool has_position = false;
  std::vector<double> position_mm;
  bool has_spindle = false;
  std::vector<double> spindle_rpm;
  bool has_coolant = false;
  std::vector<CoolantState> coolant;

  // Experiments: a recording made of separate runs (several files, or the sheets of a workbook).
  // Row r belongs to experiment experiment[r]; empty = a single experiment. ConcatenateExperiments
  // shifts each run's clock so time keeps increasing, with a gap longer than any trend window.
  std::vector<int> experiment;
  std::vector<std::string> experiment_names;

  Eigen::Index Rows() const { return static_cast<Eigen::Index>(time_s.size()); }
  int ExperimentOf(Eigen::Index row) const;
  int ExperimentCount() const;
  std::optional<std::size_t> TemperatureIndex(const std::string& name) const;
  std::optional<std::size_t> ErrorIndex(const std::string& name) const;
  // File line of a row for error messages (0 if unknown).
  int LineOf(Eigen::Index row) const;
};

// The rows given (in that order) as a new series; keeps names and metadata.
ThermalSeries SelectRows(const ThermalSeries& series, const std::vector<Eigen::Index>& rows);

// Several cleaned recordings of the same machine as one series of experiments (one per part,
// named by its source). Error channels must be the same in every part (InputError naming the part
// otherwise); temperature sensors missing from some part are dropped, with a warning. Each part's
// time is shifted to start kExperimentGapS after the previous part's end.
inline constexpr double kExperimentGapS = 7 * 24 * 3600.0;
ThermalSeries ConcatenateExperiments(const std::vector<ThermalSeries>& parts, std::vector<std::string>* warnings);

// The median time step between consecutive rows in s (0 with fewer than 2 rows): the recording's
// sample interval, robust to gaps and to the joins between experiments.
double MedianTimeStepS(const ThermalSeries& series);

// The duration of the longest single experiment in s (the whole series when it is one).
double LongestExperimentS(const ThermalSeries& series);

// Keeps only the named temperature sensors, in that order (InputError naming the sensor when absent).
ThermalSeries SelectTemperatureSensors(const ThermalSeries& series, const std::vector<std::string>& names);

// Keeps only the named error channels (InputError naming the channel when absent).
ThermalSeries SelectErrorChannels(const ThermalSeries& series, const std::vector<std::string>& names);

// A maximal run of rows at one spindle speed within one experiment: fl_thermal's programme is a
// sequence of heating (rpm > 0) and cooling (rpm = 0) blocks. A series without spindle speed is
// one block per experiment.
struct SpeedBlock {
  int index = 0;
  double spindle_rpm = 0;
  Eigen::Index first_row = 0;
  Eigen::Index last_row = 0;  // inclusive
  double start_s = 0;
  double end_s = 0;
};
std::vector<SpeedBlock> SpeedBlocks(const ThermalSeries& series);

}  // namespace trueaxis::thermal
