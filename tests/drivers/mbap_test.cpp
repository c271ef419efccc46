// MBAP framing: what the client sends is what a server parses, and every
// wrong answer is told apart (another transaction, unit, function; short data).
#include <gtest/gtest.h>

#include <vector>

#include "trueaxis/drivers/mbap.hpp"

namespace trueaxis::drivers::mbap {
namespace {

TEST(Mbap, ReadRequestRoundTripsThroughTheServerSide) {
  std::uint8_t frame[kMaxFrameBytes];
  const std::size_t n = EncodeRead(frame, 0x1234, 7, kReadInputRegisters, 16, 40);
  EXPECT_EQ(FrameLength({frame, n}), static_cast<int>(n));
  EXPECT_EQ(FrameLength({frame, n - 1}), 0);  // incomplete
  ParsedRequest q;
  ASSERT_TRUE(ParseRequest({frame, n}, &q));
  EXPECT_EQ(q.head.transaction, 0x1234);
  EXPECT_EQ(q.head.unit, 7);
  EXPECT_EQ(q.head.function, kReadInputRegisters);
  EXPECT_EQ(q.head.address, 16);
  EXPECT_EQ(q.head.count, 40);

  std::vector<std::uint16_t> regs(40);
  for (int i = 0; i < 40; ++i) regs[i] = static_cast<std::uint16_t>(1000 * i + 7);
  std::uint8_t reply[kMaxFrameBytes];
  const std::size_t r = EncodeRegistersReply(reply, q.head, regs.data());
  std::vector<std::uint16_t> got(40);
  EXPECT_EQ(ParseReply({reply, r}, q.head, got.data(), nullptr, nullptr), Reply::kOk);
  EXPECT_EQ(got, regs);
}

TEST(Mbap, WrongTransactionUnitFunctionOrLengthIsRefused) {
  Request asked{9, 1, kReadInputRegisters, 0, 4};
  std::uint16_t regs[4] = {1, 2, 3, 4}, got[4];
  std::uint8_t reply[kMaxFrameBytes];
  Request other = asked;
  other.unit = 2;
  std::size_t n = EncodeRegistersReply(reply, other, regs);
  EXPECT_EQ(ParseReply({reply, n}, asked, got, nullptr, nullptr), Reply::kMismatch);
  other = asked;
  other.transaction = 10;
  n = EncodeRegistersReply(reply, other, regs);
  EXPECT_EQ(ParseReply({reply, n}, asked, got, nullptr, nullptr), Reply::kMismatch);
  other = asked;
  other.function = kReadHoldingRegisters;
  n = EncodeRegistersReply(reply, other, regs);
  EXPECT_EQ(ParseReply({reply, n}, asked, got, nullptr, nullptr), Reply::kMismatch);
  other = asked;
  other.count = 3;  // fewer registers than asked
  n = EncodeRegistersReply(reply, other, regs);
  EXPECT_EQ(ParseReply({reply, n}, asked, got, nullptr, nullptr), Reply::kMalformed);
  std::uint8_t code = 0;
  n = EncodeException(reply, asked, kGatewayTargetFailed);
  EXPECT_EQ(ParseReply({reply, n}, asked, got, nullptr, &code), Reply::kException);
  EXPECT_EQ(code, kGatewayTargetFailed);
}

TEST(Mbap, WriteMultipleAndItsEcho) {
  std::uint8_t frame[kMaxFrameBytes];
  const std::uint16_t values[6] = {0xFFFF, 0xFF85, 0, 40, 0, 0};
  const std::size_t n = EncodeWriteRegisters(frame, 5, 1, 16, values);
  ParsedRequest q;
  ASSERT_TRUE(ParseRequest({frame, n}, &q));
  EXPECT_EQ(q.head.count, 6);
  EXPECT_EQ(WordAt(q.values, 1), 0xFF85);
  std::uint8_t reply[kMaxFrameBytes];
  const std::size_t r = EncodeWriteReply(reply, q);
  EXPECT_EQ(ParseReply({reply, r}, q.head, nullptr, nullptr, nullptr), Reply::kOk);
}

TEST(Mbap, ReadWriteMultipleCarriesBothPartsAndAnswersTheRead) {
  std::uint8_t frame[kMaxFrameBytes];
  const std::uint16_t values[4] = {0xFFFF, 0xFF85, 0, 40};
  const std::size_t n = EncodeWriteAndRead(frame, 77, 1, 100, 40, 16, values);
  EXPECT_EQ(n, kHeaderBytes + 10 + 8);
  ParsedRequest q;
  ASSERT_TRUE(ParseRequest({frame, n}, &q));
  EXPECT_EQ(q.head.function, kReadWriteMultipleRegisters);
  EXPECT_EQ(q.head.address, 100);  // the read part
  EXPECT_EQ(q.head.count, 40);
  EXPECT_EQ(q.write_address, 16);
  EXPECT_EQ(q.write_count, 4);
  EXPECT_EQ(WordAt(q.values, 1), 0xFF85);
  EXPECT_FALSE(ParseRequest({frame, n - 1}, &q));  // the write part cut short
  std::vector<std::uint16_t> regs(40, 0), got(40);
  regs[3] = 0xBEEF;
  std::uint8_t reply[kMaxFrameBytes];
  ASSERT_TRUE(ParseRequest({frame, n}, &q));
  const std::size_t r = EncodeRegistersReply(reply, q.head, regs.data());
  EXPECT_EQ(ParseReply({reply, r}, q.head, got.data(), nullptr, nullptr), Reply::kOk);
  EXPECT_EQ(got, regs);
}

TEST(Mbap, BytesThatAreNotModbusTcpAreNotAFrame) {
  const char junk[] = "HTTP/1.1 400 Bad Request\r\n\r\n";
  EXPECT_EQ(FrameLength({reinterpret_cast<const std::uint8_t*>(junk), sizeof junk - 1}), -1);
}

}  // namespace
}  // namespace trueaxis::drivers::mbap
