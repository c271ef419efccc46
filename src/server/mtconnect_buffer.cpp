#include "trueaxis/server/mtconnect_buffer.hpp"

#include <algorithm>
#include <utility>

namespace trueaxis::server::mtconnect {

ObservationBuffer::ObservationBuffer(std::size_t capacity, std::size_t items)
    : ring_(std::max<std::size_t>(1, capacity)), latest_(items), checkpoint_(items) {}

BufferRange ObservationBuffer::RangeLocked() const {
  BufferRange r;
  r.capacity = ring_.size();
  r.next = next_;
  r.last = next_ - 1;
  r.first = next_ > ring_.size() ? next_ - ring_.size() : 1;
  return r;
}

BufferRange ObservationBuffer::range() const {
  std::lock_guard lock(mutex_);
  return RangeLocked();
}

void ObservationBuffer::Append(std::span<Observation> batch) {
  std::lock_guard lock(mutex_);
  for (Observation& o : batch) {
    o.sequence = next_++;
    Observation& slot = ring_[(o.sequence - 1) % ring_.size()];
    if (slot.sequence != 0) std::swap(checkpoint_[slot.item], slot);  // the oldest leaves the ring
    slot = o;
    latest_[o.item] = o;
  }
}

bool ObservationBuffer::Current(std::optional<std::uint64_t> at, const std::vector<bool>* wanted, std::vector<Observation>& out,
                                BufferRange& range) const {
  out.clear();
  std::lock_guard lock(mutex_);
  range = RangeLocked();
  auto take = [&](std::size_t item) { return !wanted || (*wanted)[item]; };
  if (!at) {
    for (std::size_t i = 0; i < latest_.size(); ++i)
      if (latest_[i].sequence != 0 && take(i)) out.push_back(latest_[i]);
    return true;
  }
  if (*at < range.first || *at > range.last) return false;
  std::vector<const Observation*> state(checkpoint_.size(), nullptr);
  for (std::size_t i = 0; i < checkpoint_.size(); ++i)
    if (checkpoint_[i].sequence != 0) state[i] = &checkpoint_[i];
  for (std::uint64_t s = range.first; s <= *at; ++s) {
    const Observation& o = ring_[(s - 1) % ring_.size()];
    state[o.item] = &o;
  }
  for (std::size_t i = 0; i < state.size(); ++i)
    if (state[i] && take(i)) out.push_back(*state[i]);
  return true;
}

bool ObservationBuffer::Sample(std::optional<std::uint64_t> from_sequence, std::size_t count, const std::vector<bool>* wanted, std::vector<Observation>& out,
                               std::uint64_t* next_sequence, BufferRange& range) const {
  out.clear();
  std::lock_guard lock(mutex_);
  range = RangeLocked();
  const std::uint64_t from = from_sequence.value_or(range.first);
  if (from < range.first || from > range.next) return false;
  std::uint64_t s = from;
  for (; s < range.next && out.size() < count; ++s) {
    const Observation& o = ring_[(s - 1) % ring_.size()];
    if (!wanted || (*wanted)[o.item]) out.push_back(o);
  }
  *next_sequence = s;
  return true;
}

}  // namespace trueaxis::server::mtconnect
