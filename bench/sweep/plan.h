#pragma once
// The sweep definition: which targets, which references, which points (bench/README.md lists the
// studies and what each reproduces from Lu et al. 2015 §7). Each study varies one knob from the
// base settings (ours, halton, roulette, secant exact, fused, no K_max):
//
//   spp        methods ours/paper/uniform/global x spp (error vs spp and vs time; Figs. 11, 12)
//   sampler    halton / halton-scrambled / random x low spp (Fig. 8)
//   kmax       K_max at K = 200 (Fig. 9)
//   balance    paper / min1 / roulette rounding of K_m (Eq. 12)
//   search     secant / binary x search depth at K = 200 (Fig. 5: depth 3)
//   structure  per-image vs fused passes (timing; same images)
//   paper      the paper's Figs. 11-13 at its spp (63, 252, 1008, 63 000 on the bike; car1 Fig. 13)
//
// spp above 1000 are F equal progressive frames of K = spp / F <= 1000 (the kernels' sequences
// advance per frame, so F frames of K samples are one estimate with F K samples).
#include <filesystem>
#include <string>
#include <vector>

#include "bench/sweep/reference_cache.h"
#include "render/settings.h"

namespace nf::bench {

struct Point {
  std::string study;
  std::string target;  // Target::name()
  render::SamplingSettings settings;
  int frames = 1;
  int spp() const { return settings.spp * frames; }
};

struct Plan {
  std::string mode;                   // "quick" | "full"
  std::vector<std::string> closeups;  // presets, or luminaire manifests (*.json, e.g. imported)
  int closeup_res = 128;
  double closeup_scale = 1.0;  // preset image resolution scale
  bool scene = true;
  std::filesystem::path scene_file;
  int scene_width = 320, scene_height = 180;
  ReferenceSpec closeup_reference, scene_reference;
  int breakdown_spp = 200;  // the scene's full-frame breakdown (paper Fig. 10: 200 spp)
  int breakdown_reps = 3;
  int max_reps = 3;              // timing repetitions of a cheap point (fastest kept)
  double rep_budget_ms = 400.0;  // repeat only points cheaper than this
  std::vector<Point> points;
};

struct PlanOptions {
  bool quick = false;
  std::vector<std::string> closeups;  // empty: the mode's default
  std::vector<std::string> studies;   // empty: all
  bool scene = true;
  std::filesystem::path scene_file;
  int scene_width = 0, scene_height = 0, closeup_res = 0;  // 0: the mode's default
  int reference_frames = 0;                                // 0: the mode's default
  int max_spp = 0;  // > 0: leave out points above this spp (except the `paper` study's); 0: all
};

Plan make_plan(const PlanOptions& options);
// The close-up's name for an entry of --luminaires: a preset's name, or a manifest's file stem.
std::string closeup_label(const std::string& entry);
std::vector<std::string> study_names();

// spp -> (K, frames): K = spp up to 1000, else the fewest equal frames of K <= 1000.
void set_spp(Point& p, int spp);

}  // namespace nf::bench
