#pragma once
// MonitorBackend: what the web front end (web::WebServer) needs from whatever runs the machines —
// one machine under `trueaxis run` (RunBackend), a synthetic shop (SyntheticShop, for the demo
// and the load test), or the workshop server (server::Shop, bound at merge). Every call may come
// from any HTTP worker thread at any time: implementations are thread-safe, and answer from
// memory (no call waits on a machine's I/O), so a shop of 1,000 machines is listed in one call.
//
// Errors: a machine, axis, alarm or revision that does not exist throws BackendError(404, ...);
// an operation the machine refuses in its current state throws BackendError(409, ...). The
// message is shown to the user as is.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "trueaxis/runtime/machine_view.hpp"

namespace trueaxis::web {

class BackendError : public std::runtime_error {
 public:
  BackendError(int http_status, const std::string& message) : std::runtime_error(message), status_(http_status) {}
  int status() const { return status_; }

 private:
  int status_;
};

// One machine's live state, one row of the shop overview: the one vocabulary of both HTTP servers
// (runtime/machine_view.hpp: axes, channels, alarms, coolant and override, the model in use).
using MachineSummary = runtime::MachineView;

// One live sample: the values of every channel and axis at one instant, in the order of
// LiveSeries::channels / axes.
struct LiveSample {
  std::uint64_t sequence = 0;  // increases by one per sample, per machine
  double unix_s = 0;
  std::vector<double> temp_c;
  std::vector<double> correction_um;
};

struct LiveSeries {
  std::vector<std::string> channels;
  std::vector<std::string> axes;
  std::uint64_t last_sequence = 0;  // the newest sample's sequence (0: none yet)
  std::vector<LiveSample> samples;  // newer than the asked-for sequence, oldest first
};

// An ISO 230-2 style figure of the model in use, before and after compensation.
struct ModelFigure {
  std::string axis;
  std::string quantity;  // e.g. "E (bidirectional systematic deviation), state warm"
  double before_um = 0;
  double after_um = 0;
  std::string source;    // where the figure comes from (a report file, the model's fit summary)
};

struct ModelRevision {
  std::string revision;
  std::string sha256;
  std::string label;     // file or note
  double loaded_unix_s = 0;
};

// What the machine page shows of its models beyond the one in use (MachineSummary::model).
struct ModelInfo {
  std::string label;     // the model in use, as a user reads it
  std::vector<ModelRevision> available;  // revisions that can be loaded (newest last)
  std::vector<ModelFigure> figures;
};

struct MachineDetail {
  MachineSummary summary;
  ModelInfo model;
};

struct AlarmEntry {
  std::string id;          // unique within the backend
  std::string machine_id;
  std::string name;
  std::string message;
  double raised_unix_s = 0;
  bool active = true;      // the condition still holds
  bool acknowledged = false;
  std::string acknowledged_by;
  double acknowledged_unix_s = 0;
};

struct HistoryPoint {
  double unix_s = 0;
  double value = 0;
};
struct HistoryTrace {
  std::string name;        // channel or axis
  std::string unit;        // "C" or "um"
  std::vector<HistoryPoint> points;
};
struct HistorySeries {
  double from_unix_s = 0, to_unix_s = 0;
  std::vector<HistoryTrace> temperatures;
  std::vector<HistoryTrace> corrections;
  bool decimated = false;  // fewer points than stored were returned (max_points)
};

// CSV: one table (temperatures wide: one row per instant; corrections long); xlsx: every table.
// Who asks for an operation: the session's user and the client's address, for backends that keep
// their own record of changes (the workshop server records model changes with who and from where).
struct Actor {
  std::string user;
  std::string remote;
};

enum class ExportFormat { kCsvTemperature, kCsvCompensation, kXlsx };
struct ExportFile {
  std::string file_name;     // suggested download name
  std::string content_type;
  std::string bytes;
};

class MonitorBackend {
 public:
  virtual ~MonitorBackend() = default;
  // Short description for the page title and logs ("1 machine: vmc850", "shop: 1000 machines").
  virtual std::string Describe() const = 0;

  // ---- views ----
  virtual std::vector<MachineSummary> ListMachines() const = 0;
  virtual MachineDetail Machine(const std::string& id) const = 0;
  // Samples newer than `after_sequence` (0: everything kept), at most `max_samples`, newest kept.
  virtual LiveSeries Live(const std::string& id, std::uint64_t after_sequence, std::size_t max_samples) const = 0;
  virtual HistorySeries History(const std::string& id, double from_unix_s, double to_unix_s,
                                std::size_t max_points) const = 0;
  // Active and recent alarms of every machine (newest first), at most `limit`.
  virtual std::vector<AlarmEntry> Alarms(std::size_t limit) const = 0;

  // ---- operations (the web server checks the role and writes the audit log) ----
  virtual void SetAxisEnabled(const Actor& who, const std::string& id, const std::string& axis, bool enabled) = 0;
  virtual void AcknowledgeAlarm(const Actor& who, const std::string& alarm_id) = 0;
  // `state` "" clears the override (the CNC's own coolant state is used again).
  virtual void SetCoolantOverride(const Actor& who, const std::string& id, const std::string& state) = 0;
  // `revision`: one of MachineDetail::model.available[].revision (the backend's name for a model
  // it can load: a revision number, a slot, a file).
  virtual void LoadModelRevision(const Actor& who, const std::string& id, const std::string& revision) = 0;
  // Back to the model in use before the current one; returns the revision now in use.
  virtual std::string RollbackModel(const Actor& who, const std::string& id) = 0;
  virtual ExportFile Export(const std::string& id, double from_unix_s, double to_unix_s, ExportFormat format) const = 0;
};

}  // namespace trueaxis::web
