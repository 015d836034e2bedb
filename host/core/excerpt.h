#pragma once
// Quoting input in messages (docs/robustness.md, "Messages"): every reader that echoes what a file,
// a script or an option held (a token, a key, a line) passes it through excerpt(), so a 20 MB
// token, terminal escape bytes or binary garbage become a short, printable excerpt.
#include <cstddef>
#include <string>
#include <string_view>

namespace nf {

// `text` as a message quotes it: at most `max` characters (default 32), bytes outside printable
// ASCII (and the backslash) as \xNN, "..." when cut.
std::string excerpt(std::string_view text, std::size_t max = 32);

}  // namespace nf
