#include "trueaxis/drivers/mbap.hpp"

namespace trueaxis::drivers::mbap {
namespace {

std::uint16_t U16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
void PutU16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v & 0xFF);
}
// Writes the MBAP header for a PDU of `pdu_bytes`; returns the frame length.
std::size_t Header(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit, std::size_t pdu_bytes) {
  PutU16(out, transaction);
  PutU16(out + 2, 0);
  PutU16(out + 4, static_cast<std::uint16_t>(1 + pdu_bytes));
  out[6] = unit;
  return kHeaderBytes + pdu_bytes;
}

}  // namespace

std::uint16_t WordAt(const std::uint8_t* be, int index) { return U16(be + 2 * index); }

int FrameLength(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeaderBytes) return 0;
  const int protocol = U16(bytes.data() + 2);
  const int length = U16(bytes.data() + 4);  // unit id + PDU
  const std::size_t frame = 6 + static_cast<std::size_t>(length);
  if (protocol != 0 || length < 2 || frame > kMaxFrameBytes) return -1;
  return bytes.size() < frame ? 0 : static_cast<int>(frame);
}

std::size_t EncodeRead(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit, std::uint8_t function,
                       std::uint16_t address, std::uint16_t count) {
  std::uint8_t* pdu = out + kHeaderBytes;
  pdu[0] = function;
  PutU16(pdu + 1, address);
  PutU16(pdu + 3, count);
  return Header(out, transaction, unit, 5);
}

std::size_t EncodeWriteRegisters(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit,
                                 std::uint16_t address, std::span<const std::uint16_t> values) {
  std::uint8_t* pdu = out + kHeaderBytes;
  pdu[0] = kWriteMultipleRegisters;
  PutU16(pdu + 1, address);
  PutU16(pdu + 3, static_cast<std::uint16_t>(values.size()));
  pdu[5] = static_cast<std::uint8_t>(2 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) PutU16(pdu + 6 + 2 * i, values[i]);
  return Header(out, transaction, unit, 6 + 2 * values.size());
}

std::size_t EncodeWriteAndRead(std::uint8_t* out, std::uint16_t transaction, std::uint8_t unit,
                               std::uint16_t read_address, std::uint16_t read_count, std::uint16_t write_address,
                               std::span<const std::uint16_t> values) {
  std::uint8_t* pdu = out + kHeaderBytes;
  pdu[0] = kReadWriteMultipleRegisters;
  PutU16(pdu + 1, read_address);
  PutU16(pdu + 3, read_count);
  PutU16(pdu + 5, write_address);
  PutU16(pdu + 7, static_cast<std::uint16_t>(values.size()));
  pdu[9] = static_cast<std::uint8_t>(2 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) PutU16(pdu + 10 + 2 * i, values[i]);
  return Header(out, transaction, unit, 10 + 2 * values.size());
}

const char* ReplyName(Reply r) {
  switch (r) {
    case Reply::kOk: return "ok";
    case Reply::kException: return "exception";
    case Reply::kMismatch: return "mismatched reply (transaction, unit id or function)";
    case Reply::kMalformed: return "malformed reply";
  }
  return "?";
}

Reply ParseReply(std::span<const std::uint8_t> frame, const Request& request, std::uint16_t* registers,
                 std::uint8_t* bits, std::uint8_t* exception) {
  if (frame.size() < kHeaderBytes + 2) return Reply::kMalformed;
  const std::uint8_t* p = frame.data();
  if (U16(p) != request.transaction || p[6] != request.unit) return Reply::kMismatch;
  const std::uint8_t* pdu = p + kHeaderBytes;
  const std::size_t pdu_len = frame.size() - kHeaderBytes;
  if (pdu[0] == (request.function | 0x80)) {
    if (exception) *exception = pdu[1];
    return Reply::kException;
  }
  if (pdu[0] != request.function) return Reply::kMismatch;
  switch (request.function) {
    case kReadHoldingRegisters:
    case kReadInputRegisters:
    case kReadWriteMultipleRegisters: {
      const std::size_t bytes = 2u * request.count;
      if (pdu[1] != bytes || pdu_len != 2 + bytes) return Reply::kMalformed;
      for (int i = 0; i < request.count; ++i) registers[i] = U16(pdu + 2 + 2 * i);
      return Reply::kOk;
    }
    case kReadCoils: {
      const std::size_t bytes = (request.count + 7u) / 8u;
      if (pdu[1] != bytes || pdu_len != 2 + bytes) return Reply::kMalformed;
      for (int i = 0; i < request.count; ++i) bits[i] = (pdu[2 + i / 8] >> (i % 8)) & 1;
      return Reply::kOk;
    }
    case kWriteMultipleRegisters:
      if (pdu_len != 5 || U16(pdu + 1) != request.address || U16(pdu + 3) != request.count) return Reply::kMalformed;
      return Reply::kOk;
    default:
      return Reply::kMalformed;
  }
}

bool ParseRequest(std::span<const std::uint8_t> frame, ParsedRequest* out) {
  *out = {};
  if (frame.size() < kHeaderBytes + 1) return false;
  const std::uint8_t* p = frame.data();
  const std::uint8_t* pdu = p + kHeaderBytes;
  const std::size_t pdu_len = frame.size() - kHeaderBytes;
  Request& h = out->head;
  h.transaction = U16(p);
  h.unit = p[6];
  h.function = pdu[0];
  switch (h.function) {
    case kReadCoils:
    case kReadHoldingRegisters:
    case kReadInputRegisters:
      if (pdu_len < 5) return false;
      h.address = U16(pdu + 1);
      h.count = U16(pdu + 3);
      return h.count >= 1 && h.count <= (h.function == kReadCoils ? 2000 : kMaxReadRegisters);
    case kWriteSingleRegister:
      if (pdu_len < 5) return false;
      h.address = U16(pdu + 1);
      h.count = 1;
      out->values = pdu + 3;
      return true;
    case kWriteMultipleRegisters:
      if (pdu_len < 6) return false;
      h.address = U16(pdu + 1);
      h.count = U16(pdu + 3);
      out->values = pdu + 6;
      return h.count >= 1 && h.count <= kMaxWriteRegisters && pdu[5] == 2 * h.count && pdu_len >= 6u + 2u * h.count;
    case kReadWriteMultipleRegisters:
      if (pdu_len < 10) return false;
      h.address = U16(pdu + 1);
      h.count = U16(pdu + 3);
      out->write_address = U16(pdu + 5);
      out->write_count = U16(pdu + 7);
      out->values = pdu + 10;
      return h.count >= 1 && h.count <= kMaxReadWriteReadRegisters && out->write_count >= 1 &&
             out->write_count <= kMaxReadWriteWriteRegisters && pdu[9] == 2 * out->write_count &&
             pdu_len >= 10u + 2u * out->write_count;
    default:
      return true;  // unknown: the caller answers kIllegalFunction
  }
}

std::size_t EncodeRegistersReply(std::uint8_t* out, const Request& request, const std::uint16_t* registers) {
  std::uint8_t* pdu = out + kHeaderBytes;
  pdu[0] = request.function;
  pdu[1] = static_cast<std::uint8_t>(2 * request.count);
  for (int i = 0; i < request.count; ++i) PutU16(pdu + 2 + 2 * i, registers[i]);
  return Header(out, request.transaction, request.unit, 2 + 2u * request.count);
}

std::size_t EncodeBitsReply(std::uint8_t* out, const Request& request, const std::uint8_t* bits) {
  std::uint8_t* pdu = out + kHeaderBytes;
  const std::size_t bytes = (request.count + 7u) / 8u;
  pdu[0] = request.function;
  pdu[1] = static_cast<std::uint8_t>(bytes);
  for (std::size_t b = 0; b < bytes; ++b) pdu[2 + b] = 0;
  for (int i = 0; i < request.count; ++i)
    if (bits[i]) pdu[2 + i / 8] |= static_cast<std::uint8_t>(1u << (i % 8));
  return Header(out, request.transaction, request.unit, 2 + bytes);
}

std::size_t EncodeWriteReply(std::uint8_t* out, const ParsedRequest& request) {
  std::uint8_t* pdu = out + kHeaderBytes;
  const Request& h = request.head;
  pdu[0] = h.function;
  PutU16(pdu + 1, h.address);
  PutU16(pdu + 3, h.function == kWriteSingleRegister ? WordAt(request.values, 0) : h.count);
  return Header(out, h.transaction, h.unit, 5);
}

std::size_t EncodeException(std::uint8_t* out, const Request& request, std::uint8_t code) {
  std::uint8_t* pdu = out + kHeaderBytes;
  pdu[0] = static_cast<std::uint8_t>(request.function | 0x80);
  pdu[1] = code;
  return Header(out, request.transaction, request.unit, 2);
}

}  // namespace trueaxis::drivers::mbap
