// nearfield: one binary, subcommands (README.md). Errors go to stderr with exit code 1;
// command-line mistakes exit with CLI11's code (non-zero) and a usage hint.
#include <cstdio>
#include <map>
#include <new>
#include <string>

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

int main(int argc, char** argv) {
  using namespace nf;
  CLI::App app{"nearfield: renderer for scenes lit by measured near-field (light-field) luminaires"};
  app.set_version_flag("--version", std::string("nearfield ") + NEARFIELD_VERSION);
  app.require_subcommand(1);
  auto& g = app::global_options();
  app.add_option("--cl-device", g.cl_device,
                 "OpenCL device: P:D index, gpu, cpu, or a name substring (default: $NEARFIELD_CL_DEVICE, "
                 "else the first GPU, else the CPU)");
  app.add_flag("-v,--verbose", g.verbose, "More diagnostics on stderr");
  app.add_flag("-q,--quiet", g.quiet, "No progress or diagnostics on stderr");
  app.parse_complete_callback([&g] {
    log::set_level(g.quiet ? log::Level::quiet : g.verbose ? log::Level::debug : log::Level::info);
  });
  for (auto& [name, add] : app::registry()) add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const auto rest = app.remaining();
    if (!rest.empty() && app.get_subcommands().empty()) {
      std::fprintf(stderr, "nearfield: unknown subcommand '%s'\nRun with --help for the list.\n", rest.front().c_str());
      return 2;
    }
    return app.exit(e);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "nearfield: error: out of memory (an allocation failed; see `render --dry-run` for estimates)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nearfield: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
