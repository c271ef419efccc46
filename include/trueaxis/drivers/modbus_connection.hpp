#pragma once
// ModbusConnection: one MODBUS TCP client connection with the behaviour both
// clients (ModbusCncLink, ModbusTemperatureSource) need on a machine's hot
// path: bounded waits (response timeout), no exceptions, no allocation per
// request once created, and reconnection that never stalls a caller for more
// than one connect timeout per reconnect_interval_s.
#include <chrono>
#include <cstdint>
#include <string>

struct _modbus;  // libmodbus' modbus_t, kept out of this header

namespace trueaxis::drivers {

struct ModbusEndpoint {
  std::string host = "127.0.0.1";
  int port = 1502;
  double response_timeout_s = 0.1;   // per request (and per connect attempt)
  double reconnect_interval_s = 0.5; // after a fault, calls fail at once until this has passed

  bool IsValid(std::string* why) const;
};

class ModbusConnection {
 public:
  explicit ModbusConnection(ModbusEndpoint endpoint);
  ~ModbusConnection();
  ModbusConnection(const ModbusConnection&) = delete;
  ModbusConnection& operator=(const ModbusConnection&) = delete;

  // True when connected, or when a (throttled) reconnect attempt succeeds now.
  // `just_connected` tells the caller to redo its handshake.
  // `ignore_throttle` makes a deliberate connect try now.
  bool Ensure(bool* just_connected, bool ignore_throttle = false);
  bool connected() const { return connected_; }
  // Marks the link broken (closes the socket, starts the reconnect throttle)
  // and records why.
  void Fault(const char* what);
  void Close();

  // Requests to unit `unit`; each returns false (and calls Fault) on any error.
  bool ReadInputRegisters(int unit, int address, int count, std::uint16_t* out);
  bool ReadHoldingRegisters(int unit, int address, int count, std::uint16_t* out);
  bool ReadCoils(int unit, int address, int count, std::uint8_t* out);
  bool WriteRegisters(int unit, int address, int count, const std::uint16_t* values);
  // FC 23: writes `write_count` registers from `write_address`, then reads `read_count` from
  // `read_address`, in one transaction.
  bool WriteAndReadRegisters(int unit, int write_address, int write_count, const std::uint16_t* values,
                             int read_address, int read_count, std::uint16_t* out);
  // The MODBUS exception code the device answered the last request with (0: it did not).
  int last_exception() const { return last_exception_; }

  // Why the last fault happened ("" when none yet). Not for the hot path.
  const std::string& last_error() const { return last_error_; }
  std::uint64_t fault_count() const { return faults_; }
  std::uint64_t connect_count() const { return connects_; }
  const ModbusEndpoint& endpoint() const { return endpoint_; }

 private:
  bool Check(int rc, int expected, const char* what);
  void NoteError(const char* what, int err);
  ModbusEndpoint endpoint_;
  _modbus* ctx_ = nullptr;
  bool connected_ = false;
  std::chrono::steady_clock::time_point next_attempt_{};
  std::string last_error_;
  const char* last_what_ = nullptr;  // static strings only
  int last_errno_ = 0;
  int last_exception_ = 0;
  std::uint64_t faults_ = 0;
  std::uint64_t connects_ = 0;
};

}  // namespace trueaxis::drivers
