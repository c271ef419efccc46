#pragma once
// CPU time a running std::thread has used (for the shop's statistics and the
// scale benchmark: CPU per 1,000 machines).
#include <pthread.h>
#include <time.h>

#include <thread>

namespace trueaxis::drivers {

inline double ThreadCpuSeconds(std::thread& t) {
  if (!t.joinable()) return 0;
  clockid_t id;
  timespec ts{};
  if (pthread_getcpuclockid(t.native_handle(), &id) != 0 || clock_gettime(id, &ts) != 0) return 0;
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace trueaxis::drivers
