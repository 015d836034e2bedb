// nearfield serve
// Runs `reference` and `render` command lines read from stdin in this one process, one after the
// other, until stdin ends (docs/cluster.md, "Per-part cost"): nearfield-cluster's Ray workers keep
// one such process each, so a part costs neither a process start (the dynamic loader relocates
// ~260 shared libraries: ~0.3 CPU-s on the development machine) nor, for a reference, loading its
// luminaires again (render/reference_run.h keeps the last scene's in memory).
//
// Request: one line, a JSON array of the arguments (without the program name), e.g.
//   ["-q", "reference", "scene.json", "--spp", "64", "--tile", "0,0,8,8", "--part", "p.nfpart"]
// Answer: one line on stdout, `nearfield-serve {"exit_code": N, "error": "..."}`; lines before it
// (a command's own output) are not part of the protocol.
#include <cstdio>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/command.h"

namespace nf::app {
namespace {

// The subcommand of a request (its first word that is not a global option or its value).
std::string subcommand(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--cl-device") {
      ++i;
      continue;
    }
    if (!args[i].empty() && args[i][0] == '-') continue;
    return args[i];
  }
  return "";
}

void answer(int code, const std::string& error) {
  nlohmann::json j{{"exit_code", code}, {"error", error}};
  std::fputs(("nearfield-serve " + j.dump() + "\n").c_str(), stdout);
  std::fflush(stdout);
}

void run_serve() {
  static const std::set<std::string> allowed{"reference", "render"};
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    std::vector<std::string> args;
    try {
      args = nlohmann::json::parse(line).get<std::vector<std::string>>();
    } catch (const std::exception& e) {
      answer(2, fmt::format("nearfield serve: a request is a JSON array of strings ({})", e.what()));
      continue;
    }
    const std::string sub = subcommand(args);
    if (!allowed.count(sub)) {
      answer(2, fmt::format("nearfield serve: runs reference and render only, not '{}'", sub));
      continue;
    }
    std::fflush(stdout);
    const CommandResult r = run_command_line(args, false);
    std::fflush(stdout);
    answer(r.exit_code, r.message);
  }
}

const CommandRegistration reg("serve", [](CLI::App& app) {
  auto* cmd =
      app.add_subcommand("serve",
                         "Run reference/render command lines read from stdin (JSON arrays), one process for many parts "
                         "(nearfield-cluster's workers, docs/cluster.md)");
  cmd->callback([] { run_serve(); });
});

}  // namespace
}  // namespace nf::app
