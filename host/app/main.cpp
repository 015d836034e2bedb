// nearfield: one binary, subcommands (README.md). Errors go to stderr with exit code 1;
// command-line mistakes exit with CLI11's code (non-zero) and a usage hint.
#include <cstdio>
#include <map>
#include <new>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/command.h"
#include "core/error.h"
#include "core/log.h"

namespace nf::app {
namespace {
std::map<std::string, AddCommand>& registry() {
  static std::map<std::string, AddCommand> r;
  return r;
}
}  // namespace

CommandRegistration::CommandRegistration(const char* name, AddCommand add) { registry()[name] = add; }

GlobalOptions& global_options() {
  static GlobalOptions g;
  return g;
}

}  // namespace nf::app

namespace nf::app {

namespace {
std::string& program_name() {  // argv[0], for CLI11's usage lines
  static std::string name = "nearfield";
  return name;
}
}  // namespace

CommandResult run_command_line(const std::vector<std::string>& args, bool to_stderr) {
  CLI::App app{"nearfield: renderer for scenes lit by measured near-field (light-field) luminaires", program_name()};
  app.set_version_flag("--version", std::string("nearfield ") + NEARFIELD_VERSION);
  app.require_subcommand(1);
  auto& g = global_options();
  g = GlobalOptions{};
  app.add_option("--cl-device", g.cl_device,
                 "OpenCL device: P:D index, gpu, cpu, or a name substring (default: $NEARFIELD_CL_DEVICE, "
                 "else the first GPU, else the CPU)");
  app.add_flag("-v,--verbose", g.verbose, "More diagnostics on stderr");
  app.add_flag("-q,--quiet", g.quiet, "No progress or diagnostics on stderr");
  app.parse_complete_callback([&g] {
    log::set_level(g.quiet ? log::Level::quiet : g.verbose ? log::Level::debug : log::Level::info);
  });
  for (auto& [name, add] : registry()) add(app);
  auto report = [&](int code, const std::string& message) {
    if (to_stderr && !message.empty()) std::fputs(message.c_str(), stderr);
    return CommandResult{code, message};
  };
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    const auto rest = app.remaining();
    if (!rest.empty() && app.get_subcommands().empty())
      return report(2,
                    fmt::format("nearfield: unknown subcommand '{}'\nRun with --help for the list.\n", rest.front()));
    if (to_stderr) return {app.exit(e), ""};
    return {e.get_exit_code(), fmt::format("nearfield: {}\n", e.what())};
  } catch (const std::bad_alloc&) {
    return report(1, "nearfield: error: out of memory (an allocation failed; see `render --dry-run` for estimates)\n");
  } catch (const std::exception& e) {
    return report(1, fmt::format("nearfield: error: {}\n", e.what()));
  }
  return {0, ""};
}

}  // namespace nf::app

int main(int argc, char** argv) {
  if (argc > 0) nf::app::program_name() = argv[0];
  std::vector<std::string> args(argv + 1, argv + argc);
  return nf::app::run_command_line(args, true).exit_code;
}
