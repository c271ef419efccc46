// core::CsvField, the one CSV field writer (history export and `history query` had two copies that
// disagreed on '\r'): quoted exactly when RFC 4180 needs it, and read back by SplitCsvFields.
#include <gtest/gtest.h>

#include "trueaxis/core/text_lines.hpp"

namespace trueaxis {
namespace {

TEST(CsvField, QuotesCommasQuotesAndBothLineBreaks) {
  EXPECT_EQ(CsvField("x_nut"), "x_nut");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("line\nbreak"), "\"line\nbreak\"");
  EXPECT_EQ(CsvField("carriage\rreturn"), "\"carriage\rreturn\"");
  EXPECT_EQ(CsvField(""), "");
}

TEST(CsvField, SplitCsvFieldsReadsBackWhatItWrites) {
  for (const std::string field : {"plain", "with, comma", "sensor 3, \"spare\""}) {
    const std::string line = "1.5," + CsvField(field) + ",end";
    const auto cells = SplitCsvFields(line);
    ASSERT_EQ(cells.size(), 3u) << line;
    if (field.find('"') == std::string::npos) EXPECT_EQ(cells[1], field) << line;  // quotes are undoubled by readers that need them
    EXPECT_EQ(cells[2], "end");
  }
}

}  // namespace
}  // namespace trueaxis
