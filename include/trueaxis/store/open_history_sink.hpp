#pragma once
// OpenHistorySink: the history named by one string, as a shop file or command
// line would give it:
//   "machine.db", "out/history.sqlite", any path      -> SQLite file (HistoryDb, created when missing)
//   "postgresql://user@host:5432/shop", "postgres://…" -> PostgreSQL (PostgresHistorySink)
// Anything else with "://" is refused (an unknown scheme is a typo, not a
// file name). Failures throw InputError naming the spec (password redacted).
#include <memory>
#include <string>

#include "trueaxis/store/history_sink.hpp"

namespace trueaxis::store {

struct HistorySinkOptions {
  std::string postgres_schema = "public";  // PostgreSQL only: the schema (namespace) of the tables
};

std::unique_ptr<HistorySink> OpenHistorySink(const std::string& spec, const HistorySinkOptions& options = {});
bool IsPostgresUrl(const std::string& spec);

}  // namespace trueaxis::store
