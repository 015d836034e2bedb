#pragma once
// The scene's light-field luminaire instances as the reference estimator's lights
// (reference/light_field_light.h, docs/reference.md): each instance points at its loaded source's
// luminaire and host SAT (render/luminaire_cache.h), with the instance's transform and intensity,
// prepared. Used by `nearfield reference` (render/reference_run.h) and by the calculation
// surfaces' reference evaluation (app/calculation_eval.h).
#include <vector>

#include "reference/light_field_light.h"
#include "render/luminaire_cache.h"
#include "scene/scene.h"

namespace nf::render {

// One light per scene luminaire, in the scene's order. The lights point into `set`, which must
// outlive them.
std::vector<ref::LightFieldLight> reference_lights(const scene::Scene& scene, const LuminaireSet& set);

}  // namespace nf::render
