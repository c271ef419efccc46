#include "trueaxis/drivers/modbus_connection.hpp"

#include <modbus.h>

#include <cerrno>
#include <cmath>

#include <fmt/format.h>

namespace trueaxis::drivers {

bool ModbusEndpoint::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (host.empty()) return fail("host is empty");
  if (port < 1 || port > 65535) return fail(fmt::format("port {} is outside 1..65535", port));
  if (!(response_timeout_s > 0 && response_timeout_s <= 60)) return fail("response_timeout_s must be in (0, 60] s");
  if (!(reconnect_interval_s >= 0 && reconnect_interval_s <= 3600)) return fail("reconnect_interval_s must be in [0, 3600] s");
  return true;
}

ModbusConnection::ModbusConnection(ModbusEndpoint endpoint) : endpoint_(std::move(endpoint)) {
  ctx_ = modbus_new_tcp_pi(endpoint_.host.c_str(), std::to_string(endpoint_.port).c_str());
  if (!ctx_) {
    last_error_ = fmt::format("cannot create a MODBUS TCP context for {}:{}", endpoint_.host, endpoint_.port);
    return;
  }
  const double t = endpoint_.response_timeout_s;
  const auto sec = static_cast<std::uint32_t>(t);
  const auto usec = static_cast<std::uint32_t>(std::lround((t - sec) * 1e6));
  modbus_set_response_timeout(ctx_, sec, usec);
  modbus_set_byte_timeout(ctx_, sec, usec);
}

ModbusConnection::~ModbusConnection() {
  if (ctx_) {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
}

// Formats the message only when it differs from the last one, so a fault that
// repeats every cycle (a module that stays down) does not allocate every cycle.
void ModbusConnection::NoteError(const char* what, int err) {
  if (what == last_what_ && err == last_errno_ && !last_error_.empty()) return;
  last_what_ = what;
  last_errno_ = err;
  last_error_ = fmt::format("{}:{}: {}: {}", endpoint_.host, endpoint_.port, what, modbus_strerror(err));
}

void ModbusConnection::Close() {
  if (ctx_ && connected_) modbus_close(ctx_);
  connected_ = false;
}

void ModbusConnection::Fault(const char* what) {
  const int err = errno;
  ++faults_;
  NoteError(what ? what : "fault", err);
  Close();
  next_attempt_ = std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(endpoint_.reconnect_interval_s));
}

bool ModbusConnection::Ensure(bool* just_connected, bool ignore_throttle) {
  if (just_connected) *just_connected = false;
  if (connected_) return true;
  if (!ctx_) return false;
  if (!ignore_throttle && std::chrono::steady_clock::now() < next_attempt_) return false;
  if (modbus_connect(ctx_) != 0) {
    Fault("connect");
    return false;
  }
  connected_ = true;
  ++connects_;
  if (just_connected) *just_connected = true;
  return true;
}

bool ModbusConnection::Check(int rc, int expected, const char* what) {
  last_exception_ = 0;
  if (rc == expected) return true;
  if (rc >= 0) errno = EMBBADDATA;
  const int err = errno;
  if (err >= EMBXILFUN && err <= EMBXGTAR) {
    // The device answered with a MODBUS exception: the link itself is fine,
    // so keep the connection; the request failed all the same.
    ++faults_;
    last_exception_ = err - MODBUS_ENOBASE;
    NoteError(what, err);
    return false;
  }
  Fault(what);
  return false;
}

bool ModbusConnection::ReadInputRegisters(int unit, int address, int count, std::uint16_t* out) {
  if (!connected_) return false;
  modbus_set_slave(ctx_, unit);
  return Check(modbus_read_input_registers(ctx_, address, count, out), count, "read input registers");
}

bool ModbusConnection::ReadHoldingRegisters(int unit, int address, int count, std::uint16_t* out) {
  if (!connected_) return false;
  modbus_set_slave(ctx_, unit);
  return Check(modbus_read_registers(ctx_, address, count, out), count, "read holding registers");
}

bool ModbusConnection::ReadCoils(int unit, int address, int count, std::uint8_t* out) {
  if (!connected_) return false;
  modbus_set_slave(ctx_, unit);
  return Check(modbus_read_bits(ctx_, address, count, out), count, "read coils");
}

bool ModbusConnection::WriteRegisters(int unit, int address, int count, const std::uint16_t* values) {
  if (!connected_) return false;
  modbus_set_slave(ctx_, unit);
  return Check(modbus_write_registers(ctx_, address, count, values), count, "write registers");
}

bool ModbusConnection::WriteAndReadRegisters(int unit, int write_address, int write_count, const std::uint16_t* values,
                                             int read_address, int read_count, std::uint16_t* out) {
  if (!connected_) return false;
  modbus_set_slave(ctx_, unit);
  return Check(modbus_write_and_read_registers(ctx_, write_address, write_count, values, read_address, read_count, out),
               read_count, "write and read registers");
}

}  // namespace trueaxis::drivers
