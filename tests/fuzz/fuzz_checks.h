#pragma once
// What a successful read must guarantee, checked by the fuzz harnesses after every input that a
// reader accepts (docs/robustness.md). A violation prints what failed and aborts, which libFuzzer
// reports as a finding like any crash: a reader that returns NaN, Inf or an inconsistent table
// is as much a bug as one that crashes.
#include <string>

#include "luminaire/goniometric.h"
#include "luminaire/rayset.h"

namespace nf::fuzz {

// Aborts with `what` unless `ok`.
void require(bool ok, const std::string& what);

// Ray sets: at least one ray; finite positions; unit directions; finite flux >= 0; finite total.
void check_rayset(const lum::RaySet& rs);

// Imports the ray set into a small light field (4 x 4 bspline2, 8 pixels, one thread) when the
// importer accepts it (an nf::Error is fine) and checks that every pixel and figure is finite.
void check_import(const lum::RaySet& rs);

// Goniometric tables after symmetry expansion: C in [0, 360] ascending (0 .. 360, or a single 0
// for rotational), gamma ascending within [0, 180], |cd| = |C| |gamma|, every cd finite and
// >= 0, a finite lumen total and finite lookups.
void check_goniometric(const lum::Goniometric& g);

}  // namespace nf::fuzz
