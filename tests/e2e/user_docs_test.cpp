// The README and docs/ speak to users: a short README, and no references they cannot follow (the
// project's issue numbers, its work log's stops, the source documents' internal numbers in the README).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "support/read_text.hpp"

namespace fs = std::filesystem;

namespace {

using trueaxis::testing::ReadText;

const std::regex kHistory(R"(\b(issue|stop) [0-9]+\b)", std::regex::icase);

TEST(UserDocs, ReadmeIsShortAndFreeOfDevelopmentHistory) {
  const std::string readme = ReadText(fs::path(TRUEAXIS_SOURCE_DIR) / "README.md");
  ASSERT_FALSE(readme.empty());
  std::size_t lines = 0;
  for (char c : readme) lines += c == '\n';
  EXPECT_LE(lines, 150u) << "README.md is for users: keep it short, put details in docs/";
  std::smatch m;
  EXPECT_FALSE(std::regex_search(readme, m, kHistory)) << "README.md says '" << m.str() << "'";
  EXPECT_FALSE(std::regex_search(readme, m, std::regex(R"(\bseed[ -]0[0-9][0-9]\b)", std::regex::icase)))
      << "README.md says '" << m.str() << "': credit a method by its name";
  for (const char* must : {"bash scripts/demo.sh", "bash scripts/test.sh", "docs/README.md"})
    EXPECT_NE(readme.find(must), std::string::npos) << must;
}

TEST(UserDocs, DocsSpeakOfNoIssuesOrStops) {
  std::size_t pages = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(TRUEAXIS_SOURCE_DIR) / "docs")) {
    if (entry.path().extension() != ".md") continue;
    ++pages;
    const std::string text = ReadText(entry.path());
    std::smatch m;
    EXPECT_FALSE(std::regex_search(text, m, kHistory)) << entry.path().filename() << " says '" << m.str() << "'";
  }
  EXPECT_GE(pages, 20u);
}

TEST(UserDocs, TheHistoryPatternMatchesWhatItShould) {
  EXPECT_TRUE(std::regex_search(std::string("(issue 10)"), kHistory));
  EXPECT_TRUE(std::regex_search(std::string("since stop 34"), kHistory));
  EXPECT_FALSE(std::regex_search(std::string("the feed stops 5 s later"), kHistory));
  EXPECT_FALSE(std::regex_search(std::string("a stop under coolant"), kHistory));
  EXPECT_FALSE(std::regex_search(std::string("(LinuxCNC issue #2435)"), kHistory));  // a public tracker, followable
}

}  // namespace
