#pragma once
// A thousand terminals are a thousand sockets (plus listeners in the virtual
// shop): raise the soft limit of open files towards the hard limit.
#include <cstddef>
#include <string>

namespace trueaxis::drivers {

// True when at least `needed` descriptors may be open; else *why says the limit.
bool EnsureOpenFileLimit(std::size_t needed, std::string* why);

}  // namespace trueaxis::drivers
