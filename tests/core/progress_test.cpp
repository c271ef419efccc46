#include "trueaxis/core/progress.hpp"

#include <algorithm>
#include <string>

#include <gtest/gtest.h>

namespace trueaxis {
namespace {

struct Capture {
  std::string text;
  ProgressLine::Sink Sink() {
    return [this](std::string_view s) { text += s; };
  }
};

int Count(const std::string& s, char c) { return static_cast<int>(std::count(s.begin(), s.end(), c)); }

// On a terminal every status rewrites the one line in place: "\r", no newline, a shorter status
// padded over the longer one before it; a note clears the line and stays.
TEST(ProgressLine, OnATerminalTheStatusIsRewrittenInPlace) {
  Capture c;
  {
    ProgressLine p("fit", true, c.Sink());
    p.Step(1, 4, "axis X: the fit with every sensor");
    p.Step(2, 4, "axis Y");
    EXPECT_EQ(Count(c.text, '\n'), 0);
    EXPECT_EQ(Count(c.text, '\r'), 2);
    const auto last = c.text.substr(c.text.rfind('\r'));
    EXPECT_EQ(last.substr(0, 21), "\r[fit]  50 % axis Y  ");  // padded over the longer status
    EXPECT_EQ(last.size(), std::string("\r[fit]  25 % axis X: the fit with every sensor").size());
    p.Note("axis X fitted");
  }
  EXPECT_NE(c.text.find("\raxis X fitted\n"), std::string::npos) << c.text;
  EXPECT_EQ(c.text.back(), '\n');  // the destructor left no status behind the note
}

// Not a terminal: no "\r" at all; the status is quiet except one plain line per tenth of the work.
TEST(ProgressLine, NotATerminalWritesOccasionalPlainLines) {
  Capture c;
  {
    ProgressLine p("thermal evaluate", false, c.Sink());
    for (std::size_t i = 0; i <= 200; ++i) p.Step(i, 200, "model ridge, fold " + std::to_string(i));
    p.Status("not counted: quiet");
    p.Note("done");
  }
  EXPECT_EQ(c.text.find('\r'), std::string::npos);
  EXPECT_EQ(Count(c.text, '\n'), 11 + 1);  // 0 %, 10 %, … 100 %, and the note
  EXPECT_NE(c.text.find("[thermal evaluate]  50 % model ridge, fold 100\n"), std::string::npos);
  EXPECT_EQ(c.text.find("quiet"), std::string::npos);
}

// An event is the status on a terminal and a line of the log otherwise.
TEST(ProgressLine, EventsAreTheStatusOnATerminalAndLinesInALog) {
  Capture tty, log;
  {
    ProgressLine a("campaign", true, tty.Sink());
    ProgressLine b("campaign", false, log.Sink());
    for (auto* p : {&a, &b}) {
      p->Event("measuring X");
      p->Event("measuring Y");
    }
  }
  EXPECT_EQ(Count(tty.text, '\n'), 0);
  EXPECT_NE(tty.text.find("\r[campaign] measuring Y"), std::string::npos);
  EXPECT_EQ(log.text, "measuring X\nmeasuring Y\n");
}

TEST(ProgressLine, NoLineIsLongerThanTheWidth) {
  Capture c;
  std::string inputs;
  for (int i = 0; i < 400; ++i) inputs += "t" + std::to_string(i) + "@lag1800s, ";
  {
    ProgressLine p("x", true, c.Sink());
    p.Step(1, 2, inputs);
    p.Note("inputs: " + inputs + "\nsecond line");
  }
  std::size_t start = 0;
  int lines = 0;
  while (start < c.text.size()) {
    std::size_t end = c.text.find_first_of("\r\n", start);
    if (end == std::string::npos) end = c.text.size();
    EXPECT_LE(Utf8Width(std::string_view(c.text).substr(start, end - start)), ProgressLine::kMaxWidth);
    start = end + 1;
    ++lines;
  }
  EXPECT_GT(lines, 40);  // the long note was wrapped, not cut
  EXPECT_NE(c.text.find("t399@lag1800s,"), std::string::npos);
  EXPECT_NE(c.text.find("\nsecond line\n"), std::string::npos);
}

TEST(WrapText, BreaksAtSpacesIndentsContinuationsAndKeepsLongWords) {
  EXPECT_EQ(WrapText("aa bb cc", 5), (std::vector<std::string>{"aa bb", "  cc"}));
  EXPECT_EQ(WrapText("  aa bb", 6), (std::vector<std::string>{"  aa", "    bb"}));
  EXPECT_EQ(WrapText("µµµµ µµµµ", 9), (std::vector<std::string>{"µµµµ µµµµ"}));  // characters, not bytes
  EXPECT_EQ(WrapText("abcdefgh ij", 4, ""), (std::vector<std::string>{"abcdefgh", "ij"}));
}

TEST(WrapText, WrapLinesWrapsEachLineOfATextOnItsOwn) {
  EXPECT_EQ(WrapLines("aa bb cc\ndd\n", 5), "aa bb\n  cc\ndd\n");
  EXPECT_EQ(WrapLines("x", 5), "x\n");
}

}  // namespace
}  // namespace trueaxis
