#pragma once
// Subcommands register themselves: each cmd_<name>.cpp defines a static CommandRegistration
// whose function adds its CLI11 subcommand and callback. main() runs them in name order.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace nf::app {

using AddCommand = void (*)(CLI::App& app);

struct CommandRegistration {
  CommandRegistration(const char* name, AddCommand add);
};

// Options every subcommand may use (set before the subcommand callback runs).
struct GlobalOptions {
  std::string cl_device;  // --cl-device
  bool verbose = false;
  bool quiet = false;
};
GlobalOptions& global_options();

// Parses and runs one command line (without the program name) with a fresh CLI11 app: what main()
// does, and what `nearfield serve` does per request. `to_stderr`: print errors there (main);
// else only return them. A command's option values are reset by its registration.
struct CommandResult {
  int exit_code = 0;
  std::string message;  // the error, as main() prints it ("" on success)
};
CommandResult run_command_line(const std::vector<std::string>& args, bool to_stderr);

}  // namespace nf::app
