#pragma once
// Runs a Plan: builds the targets, loads or renders their references, renders every point
// (timing repetitions for cheap ones), measures the error against the reference and writes
//
//   <out>/points.csv      one row per point: settings, per-step ms, samples/s, ΔE76, rel. MSE, bias
//   <out>/references.csv  one row per target: cache key and file, spp, time, the reference's noise
//   <out>/breakdown.csv   full frames of the scene with Step 0 forced (paper Fig. 10), per category
//   <out>/meta.json       machine, load at start and end, mode, targets, wall time
//
// Column meanings are in bench/README.md. Tables are rewritten after each target, so an
// interrupted sweep leaves complete files for the targets done.
#include <filesystem>
#include <string>

#include "bench/sweep/plan.h"

namespace nf::bench {

struct RunOptions {
  std::filesystem::path out_dir;
  std::filesystem::path cache_dir;
  bool refresh_references = false;
  std::string cl_device;
  std::string command_line;
};

void run_sweep(const Plan& plan, const RunOptions& options);

}  // namespace nf::bench
