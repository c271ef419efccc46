// core/json_text.hpp: a JSON syntax error names the file, its line and column, and the reason,
// without the library's internal tag.
#include "trueaxis/core/json_text.hpp"

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {
namespace {

TEST(ParseJsonOrThrow, NamesLineAndColumnWithoutTheLibrarysTag) {
  EXPECT_EQ(ParseJsonOrThrow("{\"a\": [1, 2]}", "m.json")["a"][1], 2);
  try {
    ParseJsonOrThrow("{\n  \"a\": 1,\n  \"b\": }\n", "m.json");
    FAIL() << "parsed broken JSON";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.line(), 3) << what;
    EXPECT_EQ(what.rfind("m.json:3: not valid JSON (column 8): syntax error", 0), 0u) << what;
    EXPECT_EQ(what.find("json.exception"), std::string::npos) << what;
    EXPECT_EQ(what.find("parse error at line"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace trueaxis
