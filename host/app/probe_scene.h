#pragma once
// `nearfield probe SCENE.json [-o DIR]` (docs/calculation-surfaces.md): the illuminance on every
// calculation surface of a scene, summarised per surface (E_m, E_min, E_max, U0 = E_min / E_m,
// E_min / E_max, maintenance factor applied) on stdout; with -o, per surface NAME.csv (one row
// per point) and NAME.png (false colour, app/grid_picture.h) and calculation.json (the summary).
#include <string>

#include "app/calculation_eval.h"

namespace nf::app {

// Whether `file` is a scene file (a JSON object with a "camera"), not a luminaire manifest.
bool is_scene_file(const std::string& file);

struct ProbeSceneOptions {
  std::string scene, out;
  CalcOptions calc;
};
void run_probe_scene(const ProbeSceneOptions& o);

}  // namespace nf::app
