#pragma once
// LatestValue<T>: hands the most recent value from one producer thread to one
// consumer thread (a triple buffer). Both sides are wait-free: the producer
// fills its private buffer and publishes it with one atomic exchange; the
// consumer takes the newest published buffer with one atomic exchange. Values
// are never torn and never block either side; intermediate values the consumer
// did not look at are simply overwritten (only the latest matters).
//
// Used between the I/O workers and the real-time step (docs/runtime.md,
// *Timing contract*): the step never waits for an I/O thread, it reads the
// latest snapshot and judges its age. No allocation after construction (the
// three buffers are copies of the prototype; fill them in place).
#include <atomic>
#include <cstdint>

namespace trueaxis::runtime {

template <class T>
class LatestValue {
 public:
  explicit LatestValue(const T& prototype) : buffers_{prototype, prototype, prototype} {}
  LatestValue(const LatestValue&) = delete;
  LatestValue& operator=(const LatestValue&) = delete;

  // ---- producer ----
  T& Back() { return buffers_[back_]; }  // fill in place, then Publish()
  void Publish() { back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex; }

  // ---- consumer ----
  // Takes the newest published value if there is one; true when Front() changed.
  bool Fetch() {
    if (!(middle_.load(std::memory_order_acquire) & kFresh)) return false;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  const T& Front() const { return buffers_[front_]; }

 private:
  static constexpr int kIndex = 3, kFresh = 4;
  T buffers_[3];
  int back_ = 0;   // producer's
  int front_ = 1;  // consumer's
  std::atomic<int> middle_{2};
};

}  // namespace trueaxis::runtime
