#include "trueaxis/store/open_history_sink.hpp"

#include <atomic>
#include <regex>

#include <fmt/format.h>

#include "trueaxis/core/feature_missing.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {
namespace {
std::atomic<HistorySinkOpener> g_postgres_opener{nullptr};
}  // namespace

void SetPostgresHistoryOpener(HistorySinkOpener opener) { g_postgres_opener.store(opener); }

std::string RedactedUrl(const std::string& url) {
  static const std::regex password(R"(^([a-zA-Z][a-zA-Z0-9+.-]*://[^:/@?#]*):[^@/?#]*@)");
  std::string out = std::regex_replace(url, password, "$1:***@");
  static const std::regex param(R"(([?&]password=)[^&]*)");
  return std::regex_replace(out, param, "$1***");
}

bool IsPostgresUrl(const std::string& spec) { return spec.rfind("postgresql://", 0) == 0 || spec.rfind("postgres://", 0) == 0; }

std::unique_ptr<HistorySink> OpenHistorySink(const std::string& spec, const HistorySinkOptions& options) {
  if (spec.empty()) throw InputError("history", 0, "database", "empty: give a file path (SQLite) or a postgresql:// URL");
  if (IsPostgresUrl(spec)) {
    const HistorySinkOpener postgres = g_postgres_opener.load();
    if (!postgres) throw FeatureMissing("PostgreSQL");
    return postgres(spec, options);
  }
  const auto scheme = spec.find("://");
  if (scheme != std::string::npos)
    throw InputError(RedactedUrl(spec), 0, "database",
                     fmt::format("unknown scheme '{}': give a file path (SQLite) or a postgresql:// URL", spec.substr(0, scheme)));
  return std::make_unique<HistoryDb>(spec, HistoryDb::Mode::kReadWrite);
}

}  // namespace trueaxis::store
