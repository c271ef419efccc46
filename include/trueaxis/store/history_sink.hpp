#pragma once
// HistorySink: where the history writer's batches go. The embedded default is
// the SQLite file (HistoryDb); a shop that outgrows one box names a database
// server instead (see docs/history.md). One batch = one transaction: all of
// it is stored or none of it (the call throws).
#include <span>
#include <string>

#include "trueaxis/store/history_record.hpp"

namespace trueaxis::store {

class HistorySink {
 public:
  virtual ~HistorySink() = default;
  virtual void InsertBatch(std::span<const HistoryRecord> records) = 0;
  // Where the records go, for messages ("shop.db", "postgresql://host/db").
  virtual std::string Describe() const = 0;
};

}  // namespace trueaxis::store
