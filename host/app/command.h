#pragma once
// Subcommands register themselves: each cmd_<name>.cpp defines a static CommandRegistration
// whose function adds its CLI11 subcommand and callback. main() runs them in name order.
#include <CLI/CLI.hpp>

#include <string>

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

}  // namespace nf::app
