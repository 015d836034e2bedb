#pragma once
// Internal invariants that span files (a kernel's signature and the host code binding it, a
// buffer's size and the reads its callers ask for): checked in every build type, unlike assert(),
// because a broken one gives wrong images rather than a crash. A failure is a bug, not bad input:
// the message says "internal error" and names the invariant.
#include <string>

#include "core/error.h"

namespace nf {

inline void invariant(bool ok, const std::string& what) {
  if (!ok) fail("internal error: " + what);
}

}  // namespace nf
