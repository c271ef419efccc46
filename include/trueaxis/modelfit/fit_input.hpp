#pragma once
// The input of the automatic modelling (seed 000 "在线自动建模模块"): a set of
// laser-interferometer measurement files, each one THERMAL STATE of the machine
// (cold, heated to some temperature, soaked at another room temperature,
// heated with coolant on), each carrying its own temperatures per point.
//
// Where the state comes from, in order of precedence:
//   1. a campaign manifest (JSON, docs/model-file.md "Fit input"): each file
//      entry's "state" (and optional "coolant");
//   2. the file's own metadata lines: `# state: cold|heated-1|ambient-24|coolant:flood`
//      and optionally `# coolant: flood`;
//   3. nothing: the kind is left kUnknown and the fitter takes the file with the
//      lowest temperatures as the cold state (and says so in its warnings).
// A state label starting with "cold" is the cold state, "ambient" a soak at
// another room temperature, anything else a heated state; "coolant:<name>" or
// "coolant-<name>" (or `# coolant: <name>`) sets the coolant working state.
#include <limits>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/measure/measurement_file.hpp"

namespace trueaxis::model {

enum class StateKind { kUnknown, kCold, kHeated, kAmbient };
const char* StateKindName(StateKind k);

// The temperatures logged before a measurement started (the campaign's temperature_log.csv,
// docs/campaign.md), so a thermal-lag filter (thermal_lag.hpp) can start from the machine's
// past instead of the file's first reading. Empty when not known.
struct TemperatureHistory {
  static constexpr double kWindowS = 6 * 3600.0;  // kept before the start: > 6·τ for τ ≤ 1 h
  std::vector<double> time_s;                // relative to the measurement's start (< 0), ascending
  std::vector<std::vector<double>> temps_c;  // per row, parallel to the measurement's sensor_names (NaN: absent)
  std::vector<CoolantState> coolant;         // per row, when the log has a coolant column (else empty: off)
  // The measured axis's travelled path (the log's <axis>_travel_mm column, docs/campaign.md) from
  // kWindowS before the start to the measurement's end (the laser test moves the axis too): the
  // motion-heat input's history (AxisModel::motion_lag_s). Empty when the log has no such column.
  std::vector<double> travel_time_s;  // relative to the measurement's start, ascending
  std::vector<double> travel_mm;
  bool empty() const { return time_s.empty(); }
  bool HasTravel() const { return travel_time_s.size() >= 2; }
};

struct FitState {
  std::string path;    // as given (for messages and the model's sources)
  std::string sha256;  // of the file's bytes
  std::string label;   // "cold", "heated-2", ... ("" when none was given)
  StateKind kind = StateKind::kUnknown;
  CoolantState coolant = CoolantState::kOff;
  std::string axis;    // from `# axis:` (or the manifest)
  measure::Measurement measurement;
  // From the manifest's "temperature_log" and the entry's "start_time_s" (campaign clock).
  TemperatureHistory history;
  // Where that history came from, recorded in the model's sources so a re-fit
  // (--add-to-previous) rebuilds it: empty / NaN when the state has none.
  std::string temperature_log;
  std::string temperature_log_sha256;
  double start_time_s = std::numeric_limits<double>::quiet_NaN();
};

// Refuses a set of states in which one file's bytes occur twice (the same run
// given twice, in a manifest or on the command line, would count twice in the
// fit). InputError names both paths.
void RejectDuplicateStates(const std::vector<FitState>& states);

// The history of `m` from a campaign temperature log (docs/campaign.md: time_s on the campaign
// clock + t_<sensor>_c columns): the rows of the kWindowS before `start_time_s`, mapped onto m's
// sensors. InputError(log, line, column) for a bad number, a column given twice, a log that does not
// belong to m (it ends before or starts after m's start, or reads other temperatures at the start;
// the fit's manifest logs are checked the same way), or one without a column of `required_sensors`
// (the model's key sensors).
TemperatureHistory TemperatureHistoryFromLog(const std::string& log_path, const measure::Measurement& m,
                                             double start_time_s,
                                             const std::vector<std::string>& required_sensors = {});

// Kind and coolant from a label ("cold", "coolant:flood", ...). InputError-free:
// an unknown coolant name in a label is reported by the caller.
StateKind KindFromLabel(const std::string& label);

// Builds a FitState from an already-parsed measurement, reading `# state:`,
// `# coolant:` and `# axis:`; label/coolant arguments (non-empty) override them.
// Throws InputError(source, 0, "coolant", ...) for an unknown coolant name.
FitState MakeFitState(measure::Measurement m, const std::string& label_override = "",
                      const std::string& coolant_override = "", const std::string& sha256 = "");

// Reads each measurement file (measure::ParseMeasurement: canonical CSV, ecmc .dat, or a laser
// software's CSV through `read`'s column mapping) and, when manifest_path is not empty, every file
// the manifest lists (paths relative to the manifest's folder). Throws InputError naming the
// file/line/field for any bad input.
std::vector<FitState> LoadFitStates(const std::vector<std::string>& csv_paths, const std::string& manifest_path,
                                    const measure::MeasurementReadOptions& read = {});

// The measurement files a previous model was fitted on (its `sources`), for a
// re-fit that adds new measurements: each file is read again from its
// recorded path (relative paths from the current directory) and must still
// have its recorded SHA-256; its recorded state/coolant/axis are kept.
// InputError(model_path, 0, "sources[i].path") when a file is gone,
// InputError(file, 0, "sha256") when it changed since that fit.
struct CompositeModel;
// `read`: the column mapping of sources that are a laser software's export (as given to that fit).
std::vector<FitState> LoadPreviousSources(const CompositeModel& previous, const std::string& model_path,
                                          const measure::MeasurementReadOptions& read = {});

}  // namespace trueaxis::model
