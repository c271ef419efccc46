#include "trueaxis/drivers/open_file_limit.hpp"

#include <sys/resource.h>

#include <algorithm>

#include <fmt/format.h>

namespace trueaxis::drivers {

bool EnsureOpenFileLimit(std::size_t needed, std::string* why) {
  rlimit lim{};
  if (getrlimit(RLIMIT_NOFILE, &lim) != 0) return true;
  if (lim.rlim_cur != RLIM_INFINITY && lim.rlim_cur < needed) {
    lim.rlim_cur = lim.rlim_max == RLIM_INFINITY ? needed : std::min<rlim_t>(lim.rlim_max, needed);
    setrlimit(RLIMIT_NOFILE, &lim);
    getrlimit(RLIMIT_NOFILE, &lim);
  }
  if (lim.rlim_cur != RLIM_INFINITY && lim.rlim_cur < needed) {
    if (why) *why = fmt::format("needs {} open files, the limit is {} (ulimit -n)", needed, lim.rlim_cur);
    return false;
  }
  return true;
}

}  // namespace trueaxis::drivers
