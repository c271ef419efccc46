#pragma once
// The `trueaxis sim` parent subcommand. Several files attach children to it
// (`sim campaign` here, `sim serve` in cmd_sim_serve.cpp); whichever setup
// runs first creates it, the others get the same one.
#include <CLI/CLI.hpp>

namespace trueaxis::cli {

CLI::App* SimCommand(CLI::App& app);

}  // namespace trueaxis::cli
