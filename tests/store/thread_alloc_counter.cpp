// Replaced global operator new that counts allocations of the CALLING thread
// only (the history writer's own thread allocates freely; the real-time
// producer must not).
#include <cstdlib>
#include <new>

namespace trueaxis::testing {
thread_local long t_allocation_count = 0;
long ThreadAllocationCount() { return t_allocation_count; }
}  // namespace trueaxis::testing

void* operator new(std::size_t size) {
  ++trueaxis::testing::t_allocation_count;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++trueaxis::testing::t_allocation_count;
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t& t) noexcept { return ::operator new(size, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
