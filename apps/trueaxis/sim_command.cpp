#include "sim_command.hpp"

#include "command.hpp"

namespace trueaxis::cli {

CLI::App* SimCommand(CLI::App& app) {
  return CommandGroup(app, "sim", "The virtual machine tool: campaigns, MODBUS server");
}

}  // namespace trueaxis::cli
