#include "core/excerpt.h"

#include <fmt/format.h>

namespace nf {

std::string excerpt(std::string_view text, std::size_t max) {
  std::string out;
  for (std::size_t k = 0; k < text.size() && k < max; ++k) {
    const auto c = static_cast<unsigned char>(text[k]);
    if (c >= 0x20 && c < 0x7f && c != '\\')
      out.push_back(static_cast<char>(c));
    else
      out += fmt::format("\\x{:02x}", c);
  }
  if (text.size() > max) out += "...";
  return out;
}

}  // namespace nf
