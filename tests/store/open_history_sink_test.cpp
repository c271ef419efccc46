// OpenHistorySink's choice of history from one string: a path is SQLite, an unknown scheme is
// refused without showing a password, and a postgresql:// URL in a program that did not enable
// PostgreSQL (this suite does not link store_postgres) says the build lacks it.
#include "trueaxis/store/open_history_sink.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "trueaxis/core/feature_missing.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {
namespace {

TEST(OpenHistorySink, PathIsSqliteUnknownSchemeIsRefusedPasswordNeverShown) {
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_sink_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto sqlite = OpenHistorySink((dir / "h.db").string());
  EXPECT_NE(dynamic_cast<HistoryDb*>(sqlite.get()), nullptr);
  sqlite.reset();
  std::filesystem::remove_all(dir);
  try {
    OpenHistorySink("mysql://root:hunter2@localhost/shop");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown scheme 'mysql'"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("hunter2"), std::string::npos) << e.what();
  }
  EXPECT_EQ(RedactedUrl("postgresql://h/db?user=u&password=p1&x=1"), "postgresql://h/db?user=u&password=***&x=1");
  EXPECT_EQ(RedactedUrl("postgresql://shop:hunter2@db/shop"), "postgresql://shop:***@db/shop");
}

TEST(OpenHistorySink, PostgresUrlWithoutThePostgresFeatureSaysHowToGetIt) {
  for (const char* url : {"postgresql://shop@db.hall3/shop", "postgres://db/shop"}) {
    try {
      OpenHistorySink(url);
      FAIL() << url;
    } catch (const FeatureMissing& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("no PostgreSQL support"), std::string::npos) << what;
      EXPECT_NE(what.find("install-deps.sh --all"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace trueaxis::store
