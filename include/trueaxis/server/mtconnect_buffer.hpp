#pragma once
// ObservationBuffer: the MTConnect agent's bounded circular buffer of observations (docs/server.md,
// "MTConnect agent"). Each observation gets the next sequence number; once `capacity` are held the
// oldest falls out. The latest observation of every data item is kept apart from the ring, so
// /current answers for every item even when its last change left the buffer long ago, and so is
// each item's state at the oldest observation still held (the checkpoint), so /current?at=N
// answers for any N the buffer still holds.
//
// One writer (the agent's publisher, a few times a second) and any number of readers (the HTTP
// workers) share one mutex, held only to copy observations in or out: the documents are built
// outside it. Slots are reused: after the first lap no observation allocates unless its text grows.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace trueaxis::server::mtconnect {

struct Observation {
  std::uint64_t sequence = 0;  // 0: none (an item that never had one)
  std::uint32_t item = 0;      // DataItem index
  double time_unix_s = 0;
  std::string value;           // samples and events: the value or "UNAVAILABLE"; conditions: Normal | Warning | Fault | Unavailable
  std::string native_code;     // conditions: the alarm or health names
  std::string text;            // conditions: what a person reads
};

struct BufferRange {
  std::uint64_t first = 1;  // firstSequence: the oldest observation held
  std::uint64_t last = 0;   // lastSequence: the newest
  std::uint64_t next = 1;   // nextSequence of the agent: the number the next observation gets
  std::size_t capacity = 0;
};

class ObservationBuffer {
 public:
  ObservationBuffer(std::size_t capacity, std::size_t items);

  // Appends in order, numbering from range().next (each observation's `sequence` is set here).
  void Append(std::span<Observation> batch);

  BufferRange range() const;
  // Every item's latest observation (at == nullopt), or its state after observation `at`
  // (first <= at <= last, else false). Items without any observation yet are left out.
  bool Current(std::optional<std::uint64_t> at, const std::vector<bool>* wanted, std::vector<Observation>& out,
               BufferRange& range) const;
  // Up to `count` observations from sequence `from` on (range.first <= from <= range.next, else false;
  // nullopt: the oldest held) whose item is wanted (null: all); *next_sequence: the one after the
  // last examined.
  bool Sample(std::optional<std::uint64_t> from, std::size_t count, const std::vector<bool>* wanted, std::vector<Observation>& out,
              std::uint64_t* next_sequence, BufferRange& range) const;

 private:
  BufferRange RangeLocked() const;
  mutable std::mutex mutex_;
  std::vector<Observation> ring_;        // slot of sequence s: (s - 1) % capacity
  std::vector<Observation> latest_;      // per item
  std::vector<Observation> checkpoint_;  // per item: its state before range().first
  std::uint64_t next_ = 1;
};

}  // namespace trueaxis::server::mtconnect
