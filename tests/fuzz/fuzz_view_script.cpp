// libFuzzer harness: viewer scripts (host/app/view_script.h parse_script). Every failure must be
// nf::Error; a script the parser accepts names only commands of script_commands() and its typed
// arguments read back (numbers finite) without throwing, so nothing fails between frames that
// parsing could have caught (docs/viewer.md, Scripts).
#include <cmath>
#include <cstdint>
#include <string>

#include "app/view_script.h"
#include "core/error.h"
#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  return 0;
}

namespace {

void check_arguments(const nf::app::Script& s, const nf::app::ScriptCommand& c, const nf::app::ScriptCommandSpec& spec) {
  const std::size_t kinds = spec.required.size() + spec.optional.size();
  nf::fuzz::require(c.args.size() >= spec.required.size() && c.args.size() <= kinds,
                    "an accepted command has as many arguments as its entry allows");
  for (std::size_t i = 0; i < c.args.size(); ++i) {
    const auto kind = i < spec.required.size() ? spec.required[i] : spec.optional[i - spec.required.size()];
    if (kind == nf::app::ScriptArg::number)
      nf::fuzz::require(std::isfinite(nf::app::script_number(s, c, i)), "an accepted number is finite");
    if (kind == nf::app::ScriptArg::count || kind == nf::app::ScriptArg::index) (void)nf::app::script_integer(s, c, i);
    if (kind == nf::app::ScriptArg::on_off) (void)nf::app::script_switch(s, c, i);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  nf::app::Script script;
  try {
    script = nf::app::parse_script(text, "input.script");
  } catch (const nf::Error&) {
    return 0;
  }
  for (const auto& c : script.commands) {
    const auto* spec = nf::app::find_script_command(c.name);
    nf::fuzz::require(spec != nullptr, "an accepted script names only known commands");
    check_arguments(script, c, *spec);
  }
  return 0;
}
