#include "sim_command.hpp"

namespace trueaxis::cli {

CLI::App* SimCommand(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands([](CLI::App* s) { return s->get_name() == "sim"; })) return sub;
  CLI::App* sim = app.add_subcommand("sim", "The virtual machine tool: campaigns, MODBUS server");
  sim->require_subcommand(1);
  return sim;
}

}  // namespace trueaxis::cli
