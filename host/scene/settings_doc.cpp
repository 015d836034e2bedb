// The settings reference page (docs/settings.md) generated from the declarations.
#include <fmt/format.h>

#include "scene/settings.h"

namespace nf::scene {

std::string settings_markdown() {
  const RenderSettings defaults;
  std::string md =
      "| setting | scene key (under `render`) | command line | values | default | invalidates | contribution | "
      "meaning |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : settings_table())
    md += fmt::format("| `{}` | `{}` | `{}` | {} | `{}` | {} | {} | {} |\n", s.name, s.json_path, s.cli_name(),
                      s.range_text(), s.get(defaults),
                      to_string(s.effect) + (s.applies_doc.empty() ? "" : " (" + s.applies_doc + ")"), s.contribution,
                      s.doc);
  return md;
}

}  // namespace nf::scene
