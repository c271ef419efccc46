// The w1_slave text format of the kernel's w1_therm driver.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "fake_w1_tree.hpp"
#include "trueaxis/terminal/w1_slave.hpp"

namespace trueaxis::terminal {
namespace {

TEST(W1Slave, ReadsTheKernelsExampleText) {
  const auto r = ParseW1Slave("72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n72 01 4b 46 7f ff 0e 10 57 t=23125\n");
  ASSERT_EQ(r.status, W1SlaveStatus::kOk) << r.why;
  EXPECT_EQ(r.milli_c, 23125);
}

TEST(W1Slave, ReadsTemperaturesAcrossTheSensorsRange) {
  for (long milli : {-55000L, -10125L, -62L, 0L, 62L, 21500L, 84937L, 85000L, 125000L}) {
    const auto r = ParseW1Slave(testing::W1SlaveText(milli));
    ASSERT_EQ(r.status, W1SlaveStatus::kOk) << milli << ": " << r.why;
    EXPECT_EQ(r.milli_c, milli);
  }
}

TEST(W1Slave, CrcNoIsAFailedRead) {
  EXPECT_EQ(ParseW1Slave(testing::W1SlaveText(23125, false)).status, W1SlaveStatus::kCrcError);
  EXPECT_EQ(ParseW1Slave("ff ff ff ff ff ff ff ff ff : crc=c9 NO\nff ff ff ff ff ff ff ff ff t=-62\n").status,
            W1SlaveStatus::kCrcError);
}

TEST(W1Slave, AllZeroScratchpadIsNoResponseEvenThoughTheCrcSaysYes) {
  EXPECT_EQ(ParseW1Slave("00 00 00 00 00 00 00 00 00 : crc=00 YES\n00 00 00 00 00 00 00 00 00 t=0\n").status,
            W1SlaveStatus::kNoResponse);
}

TEST(W1Slave, GarbageIsMalformedWithAReason) {
  for (const char* text : {"", "\n", "hello\nworld\n", "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n",
                           "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n72 01 4b 46 7f ff 0e 10 57\n",
                           "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n72 01 4b 46 7f ff 0e 10 57 t=2x3\n",
                           "72 01 4b 46 7f ff 0e 10 57 : crc=57 MAYBE\n72 01 4b 46 7f ff 0e 10 57 t=23125\n",
                           "72 01 4b : crc=57 YES\n72 01 4b t=23125\n", "\x01\x02\xff\xfe\n\x00\x00"}) {
    const auto r = ParseW1Slave(text);
    EXPECT_EQ(r.status, W1SlaveStatus::kMalformed) << "'" << text << "'";
    EXPECT_FALSE(r.why.empty());
  }
}

TEST(W1Slave, MutatedTextsNeverPassAsAReadingTheyDoNotHold) {
  // Every single-byte change of a valid text: either still a valid reading whose value is the
  // one written in it, or refused. Never a crash, never a number from nowhere.
  const std::string good = testing::W1SlaveText(23125);
  std::mt19937 rng(7);
  int accepted = 0, refused = 0;
  for (std::size_t pos = 0; pos < good.size(); ++pos) {
    for (int k = 0; k < 40; ++k) {
      std::string text = good;
      text[pos] = static_cast<char>(rng() & 0xFF);
      const auto r = ParseW1Slave(text);
      if (r.status == W1SlaveStatus::kOk) {
        ++accepted;
        const auto t = text.rfind("t=");
        ASSERT_NE(t, std::string::npos) << text;
        EXPECT_EQ(r.milli_c, std::stol(text.substr(t + 2))) << text;
        EXPECT_NE(text.find("YES"), std::string::npos) << text;
      } else {
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(accepted, 0);  // changes inside the hex bytes the kernel already judged are not ours to re-check
}

}  // namespace
}  // namespace trueaxis::terminal
