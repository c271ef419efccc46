#include "trueaxis/store/open_history_sink.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/postgres_history_sink.hpp"

namespace trueaxis::store {

bool IsPostgresUrl(const std::string& spec) { return spec.rfind("postgresql://", 0) == 0 || spec.rfind("postgres://", 0) == 0; }

std::unique_ptr<HistorySink> OpenHistorySink(const std::string& spec, const HistorySinkOptions& options) {
  if (spec.empty()) throw InputError("history", 0, "database", "empty: give a file path (SQLite) or a postgresql:// URL");
  if (IsPostgresUrl(spec)) return std::make_unique<PostgresHistorySink>(PostgresHistoryOptions{spec, options.postgres_schema});
  const auto scheme = spec.find("://");
  if (scheme != std::string::npos)
    throw InputError(RedactedUrl(spec), 0, "database",
                     fmt::format("unknown scheme '{}': give a file path (SQLite) or a postgresql:// URL", spec.substr(0, scheme)));
  return std::make_unique<HistoryDb>(spec, HistoryDb::Mode::kReadWrite);
}

}  // namespace trueaxis::store
