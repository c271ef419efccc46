#pragma once
// OpenHistorySink: the history named by one string, as a shop file or command
// line would give it:
//   "machine.db", "out/history.sqlite", any path      -> SQLite file (HistoryDb, created when missing)
//   "postgresql://user@host:5432/shop", "postgres://…" -> PostgreSQL (PostgresHistorySink)
// Anything else with "://" is refused (an unknown scheme is a typo, not a
// file name). Failures throw InputError naming the spec (password redacted).
// PostgreSQL is an optional feature (module store_postgres): a program built with it calls
// store::EnablePostgresHistory() once before opening; without it a postgresql:// URL throws
// FeatureMissing.
#include <memory>
#include <string>

#include "trueaxis/store/history_sink.hpp"

namespace trueaxis::store {

struct HistorySinkOptions {
  std::string postgres_schema = "public";  // PostgreSQL only: the schema (namespace) of the tables
};

std::unique_ptr<HistorySink> OpenHistorySink(const std::string& spec, const HistorySinkOptions& options = {});
bool IsPostgresUrl(const std::string& spec);

// How a postgresql:// URL is opened: set by store::EnablePostgresHistory() (store_postgres).
using HistorySinkOpener = std::unique_ptr<HistorySink> (*)(const std::string& url, const HistorySinkOptions& options);
void SetPostgresHistoryOpener(HistorySinkOpener opener);

// The URL without its password (for messages and logs).
std::string RedactedUrl(const std::string& url);

}  // namespace trueaxis::store
