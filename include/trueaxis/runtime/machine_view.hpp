#pragma once
// MachineView: a machine's live state as every HTTP API tells it — the workshop server's control
// API (server::HttpApi, `trueaxis server status`, the MQTT status topic) and the web front end
// (web::WebServer over `run`, the workshop server or the demo shop). One vocabulary, one writer
// (MachineViewJson), so the two servers cannot drift apart: docs/server.md and docs/web.md describe
// the same object. Units are in the names; a value that is not known now (a lost sensor, a link
// that is down, a value a machine does not report) is NaN here and null in the JSON.
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace trueaxis::runtime {

inline constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

struct MachineAxisView {
  std::string name;
  bool enabled = false;  // this axis's compensation is switched on (ramps through the limiter)
  // How the compensator treats it (AxisCompensationState): full, fallback_model, geometric,
  // disabled or link_lost.
  std::string state = "link_lost";
  double position_mm = kUnknown;    // as the CNC reports it
  double correction_um = kUnknown;  // the limiter's output now handed to the CNC (physical µm, correction sign)
  double target_um = kUnknown;      // what the model asks for (NaN: hold)
  double applied_um = kUnknown;     // what the CNC reports it applies now (CNC units; the workshop server's terminals)
};

struct MachineChannelView {
  std::string name;
  double temp_c = kUnknown;
  std::string health = "lost";  // the compensator's verdict: ok, held, lost
};

struct MachineModelView {
  std::string revision;  // the model's revision ("" = no model)
  std::string sha256;    // of the model file
  std::string file;      // the file it was loaded from on the workshop server ("" when not known)
};

struct MachineView {
  std::string id;  // URL-safe ([A-Za-z0-9_.-]): the machine's path in either API
  std::string name;
  bool connected = false;            // the last read of the machine succeeded
  double updated_unix_s = kUnknown;  // time of the values (NaN: never read)
  std::vector<std::string> alarms;   // names of the active alarms
  std::string coolant;               // the coolant state the compensator uses (off, flood, mist, air)
  std::string coolant_override;      // "" = none (the CNC's own state), else the forced state
  MachineModelView model;
  std::vector<MachineAxisView> axes;
  std::vector<MachineChannelView> channels;
};

// {"id","name","connected","updated_unix_s","alarms":[…],"coolant","coolant_override","model":{…},
//  "axes":[{"name","enabled","state","position_mm","correction_um","target_um","applied_um"}],
//  "channels":[{"name","temp_c","health"}]}; coolant_override null when none.
nlohmann::json MachineViewJson(const MachineView& m);
// {"revision","sha256","file"}: the model inside a machine, also in the model-change records.
nlohmann::json ModelViewJson(const MachineModelView& m);

// "link_read|stale_input" (AlarmNames, RecordAlarmNames) → {"link_read", "stale_input"}; "" → {}.
std::vector<std::string> SplitAlarmNames(const std::string& names);

}  // namespace trueaxis::runtime
