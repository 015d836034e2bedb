#include "scene/choices.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf::scene {

void fail_unknown_choice(const std::string& what, const std::string& text, const std::vector<std::string>& names) {
  fail(fmt::format("{}: unknown value '{}' (valid: {})", what, excerpt(text), fmt::join(names, ", ")));
}

}  // namespace nf::scene
