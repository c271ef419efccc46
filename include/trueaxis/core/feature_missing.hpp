#pragma once
// FeatureMissing: what a command or an input asks for needs an optional feature that this build
// was configured without (vision, PostgreSQL, MQTT, …; docs/building.md). The message says how to
// get it; the CLI prints it and exits 1.
#include <stdexcept>
#include <string>

namespace trueaxis {

class FeatureMissing : public std::runtime_error {
 public:
  // `feature` as users know it: "vision", "PostgreSQL", "MQTT".
  explicit FeatureMissing(const std::string& feature)
      : std::runtime_error("this build has no " + feature +
                           " support: install the packages with `bash scripts/install-deps.sh --all` and rebuild") {}
};

}  // namespace trueaxis
