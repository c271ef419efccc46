#pragma once
// LiveRing: the newest live samples of one machine (a fixed number), numbered by a sequence that
// increases by one per sample, so a polling browser asks for "everything after N" and gets only
// what it has not seen. Not thread-safe by itself: its owner guards it.
#include <cstdint>
#include <deque>

#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

class LiveRing {
 public:
  explicit LiveRing(std::size_t capacity = 600) : capacity_(capacity ? capacity : 1) {}
  // Numbers the sample (sequence = last + 1) and keeps it; the oldest goes beyond the capacity.
  void Push(LiveSample sample) {
    sample.sequence = ++last_sequence_;
    samples_.push_back(std::move(sample));
    while (samples_.size() > capacity_) samples_.pop_front();
  }
  std::uint64_t last_sequence() const { return last_sequence_; }
  // Samples with sequence > after, at most max (the newest ones), oldest first.
  void CopyAfter(std::uint64_t after, std::size_t max, std::vector<LiveSample>& out) const {
    std::size_t first = samples_.size();
    while (first > 0 && samples_[first - 1].sequence > after && samples_.size() - first < max) --first;
    out.assign(samples_.begin() + static_cast<std::ptrdiff_t>(first), samples_.end());
  }

 private:
  std::size_t capacity_;
  std::uint64_t last_sequence_ = 0;
  std::deque<LiveSample> samples_;
};

}  // namespace trueaxis::web
