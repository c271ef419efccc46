#pragma once
// ShopConfig: the shop file of `trueaxis server --config shop.toml`
// (docs/server.md): where the history goes, the HTTP control API, and one
// [[machine]] per terminal. Every error is an InputError naming the file,
// line and key; unknown keys are errors. Relative paths are resolved against
// the shop file's folder.
#include <string>
#include <vector>

#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/station/installation_config.hpp"

namespace trueaxis::server {

struct MachineConfig {
  std::string name;                 // unique; [A-Za-z0-9_.-], ≤ 31 characters (history names "name/axis")
  std::string host = "127.0.0.1";   // the terminal (IPv4 address)
  int port = 1502;
  int pmc_unit_id = 1;              // the PMC window
  int first_rtd_unit_id = 2;        // ADAM-6015 modules, 7 channels each, in channel order
  std::vector<std::string> axes;    // CNC axis names in window order (count checked against the window)
  std::vector<std::string> channels;// rtd_channels: RTD channel names in module order ([channels] stays the model→channel map)
  std::string model_file;           // the model in force at start
  double period_s = 0.1;            // poll period: read → step → write once per period
  double temperature_period_s = 1.0;// the ADAM-6015 values are read this often (temperatures change over
                                    // minutes; each module read is one more request per cycle)
  double response_timeout_s = 0.2;  // per request (a connect attempt has connect_timeout_s)
  double connect_timeout_s = 0.5;
  double min_backoff_s = 0.1;       // reconnect delay after a fault, doubling up to max_backoff_s
  double max_backoff_s = 5.0;
  std::vector<runtime::AxisInterface> axis_interfaces;  // one per axis, in `axes` order
  // The machine as an installation sees it (station::Installation), in the form `run` reads: its
  // compensator's tables (installation.compensator: the one copy of its options, the temperature
  // judge's limits included), model, periods and axes above, its [machine.signal] table (the
  // temperature pipeline) and thermal_channels (a data-driven thermal model on these axes).
  station::InstallationConfig installation;
  int line = 0;                     // where it is in the shop file
};

// [mqtt]: each machine's live values to an MQTT broker for other consumers (docs/mqtt.md).
struct MqttConfig {
  std::string broker;                  // "tcp://host:port"; "" = no MQTT
  std::string shop = "shop";           // the second topic level: <topic_root>/<shop>/<machine>/...
  std::string topic_root = "trueaxis";
  std::string client_id = "trueaxis-server";
  int qos = 1;
  double period_s = 1.0;               // every machine's values this often
};

struct ShopConfig {
  std::string source;
  std::string history;              // SQLite file ("" = no history). A database server goes beside it later.
  std::string audit_log;            // JSON lines of every model change (default: <history>.audit.jsonl)
  double record_interval_s = 1.0;   // per machine: every channel and axis this often, alarms on change
  std::string http_bind = "127.0.0.1";
  int http_port = 0;                // 0: no HTTP control API
  int audit_log_line = 0;           // where audit_log, [http] bind / port are in the shop file (0: not given)
  int http_bind_line = 0;
  int http_port_line = 0;
  // [server] poll_threads: the machines are polled by this many threads, machine i by thread
  // i mod poll_threads (each with its own epoll set); 1 to kMaxPollThreads.
  int poll_threads = 1;
  int poll_threads_line = 0;        // where it (or [server]) is in the shop file (0: not given)
  MqttConfig mqtt;
  std::vector<MachineConfig> machines;
};

inline constexpr int kMaxPollThreads = 64;

ShopConfig ParseShopConfig(const std::string& text, const std::string& source);
ShopConfig ReadShopConfig(const std::string& path);

}  // namespace trueaxis::server
