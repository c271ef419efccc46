#pragma once
// MODBUS TCP framing (MBAP header + PDU) for the event-loop client and the
// virtual shop's terminals: pure functions over byte buffers, no sockets, no
// allocation. Only the function codes the PMC window and the ADAM-6015 need.
//
//   MBAP: transaction id (2) | protocol id = 0 (2) | length = 1 + PDU bytes (2) | unit id (1)
//   PDU:  function code (1) | data
// All 16-bit fields big-endian (docs/protocols.md).
#include <cstddef>
#include <cstdint>
#include <span>

namespace trueaxis::drivers::mbap {

inline constexpr std::size_t kHeaderBytes = 7;   // MBAP incl. unit id
inline constexpr std::size_t kMaxFrameBytes = 260;
inline constexpr int kMaxReadRegisters = 125;
inline constexpr int kMaxWriteRegisters = 123;
inline constexpr int kMaxReadWriteReadRegisters = 125;   // FC 23
inline constexpr int kMaxReadWriteWriteRegisters = 121;

enum FunctionCode : std::uint8_t {
  kReadCoils = 1,
  kReadHoldingRegisters = 3,
  kReadInputRegisters = 4,
  kWriteSingleRegister = 6,
  kWriteMultipleRegisters = 16,
  kReadWriteMultipleRegisters = 23,  // writes, then reads (holding registers), in one transaction
};

enum ExceptionCode : std::uint8_t {
  kIllegalFunction = 1,
  kIllegalDataAddress = 2,
  kIllegalDataValue = 3,
  kGatewayTargetFailed = 0x0B,
};

// How many bytes of `bytes` the first frame takes: 0 = incomplete (wait for
// more), -1 = not MODBUS TCP (protocol id ≠ 0, length out of range): drop the link.
int FrameLength(std::span<const std::uint8_t> bytes);

// ---- client side ----
// Each returns the frame length written to `out` (≥ kMaxFrameBytes of room).
std::size_t EncodeRead(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit, std::uint8_t function,
                       std::uint16_t address, std::uint16_t count);
std::size_t EncodeWriteRegisters(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit,
                                 std::uint16_t address, std::span<const std::uint16_t> values);
// FC 23: writes `values` from `write_address`, then reads `read_count` from `read_address`.
std::size_t EncodeWriteAndRead(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit,
                               std::uint16_t read_address, std::uint16_t read_count, std::uint16_t write_address,
                               std::span<const std::uint16_t> values);

enum class Reply {
  kOk,
  kException,    // a MODBUS exception answer (code in *exception)
  kMismatch,     // another transaction, unit id or function code than asked
  kMalformed,    // wrong length or byte count
};
const char* ReplyName(Reply r);

// What was asked, to check the answer against.
struct Request {
  std::uint16_t transaction = 0;
  std::uint8_t unit = 0;
  std::uint8_t function = 0;
  std::uint16_t address = 0;
  std::uint16_t count = 0;  // registers / coils read or written (FC 23: read)
};

// Checks one complete frame against `request`. For register reads fills
// registers[0..count), for coil reads bits[0..count) (0/1).
Reply ParseReply(std::span<const std::uint8_t> frame, const Request& request, std::uint16_t* registers,
                 std::uint8_t* bits, std::uint8_t* exception);

// ---- server side ----
struct ParsedRequest {
  Request head;
  const std::uint8_t* values = nullptr;  // FC 16 / FC 06 / FC 23: big-endian words written
  std::uint16_t write_address = 0;       // FC 23: the write part (head.address/count: the read part)
  std::uint16_t write_count = 0;
};
// False when the PDU is too short for its function code or the quantity is
// out of range (answer kIllegalDataValue); an unknown function parses with count 0.
bool ParseRequest(std::span<const std::uint8_t> frame, ParsedRequest* out);
std::uint16_t WordAt(const std::uint8_t* be, int index);
// Answers, written to `out`; each returns the frame length.
std::size_t EncodeRegistersReply(std::uint8_t* out, const Request& request, const std::uint16_t* registers);
std::size_t EncodeBitsReply(std::uint8_t* out, const Request& request, const std::uint8_t* bits);
std::size_t EncodeWriteReply(std::uint8_t* out, const ParsedRequest& request);  // FC 06 echo / FC 16 address+count
std::size_t EncodeException(std::uint8_t* out, const Request& request, std::uint8_t code);

}  // namespace trueaxis::drivers::mbap
