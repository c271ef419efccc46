#pragma once
// Counts every call of the global operator new in this test binary (the
// replacement lives in alloc_counter.cpp), so tests can prove that a code
// path allocates nothing.
#include <atomic>

namespace trueaxis::testing {
extern std::atomic<long> g_allocation_count;
inline long AllocationCount() { return g_allocation_count.load(std::memory_order_relaxed); }
}  // namespace trueaxis::testing
