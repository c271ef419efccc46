#pragma once
// SpscRing: a bounded single-producer single-consumer queue with all storage
// allocated up front. The producer (the real-time loop) never blocks and never
// allocates: when the consumer falls behind, TryPush returns false and the
// caller counts the drop. Classic Lamport ring with acquire/release indices.
#include <atomic>
#include <cstddef>
#include <vector>

namespace trueaxis::runtime {

template <typename T>
class SpscRing {
 public:
  explicit SpscRing(std::size_t capacity) : slots_(RoundUp(capacity)), mask_(slots_.size() - 1) {}

  // Producer thread only.
  bool TryPush(const T& value) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= slots_.size()) return false;
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  // Consumer thread only.
  bool TryPop(T& out) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  std::size_t Capacity() const { return slots_.size(); }
  std::size_t SizeApprox() const { return head_.load() - tail_.load(); }

 private:
  static std::size_t RoundUp(std::size_t n) {
    std::size_t p = 2;
    while (p < n) p <<= 1;
    return p;
  }
  std::vector<T> slots_;
  std::size_t mask_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace trueaxis::runtime
