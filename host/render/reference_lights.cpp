#include "render/reference_lights.h"

namespace nf::render {

std::vector<ref::LightFieldLight> reference_lights(const scene::Scene& scene, const LuminaireSet& set) {
  std::vector<ref::LightFieldLight> lights;
  lights.reserve(scene.luminaires.size());
  for (std::size_t i = 0; i < scene.luminaires.size(); ++i) {
    const LuminaireSource& src = set.sources[set.source_of[i]];
    ref::LightFieldLight l;
    l.luminaire = &src.luminaire;
    l.precomputed = &src.precomputed;
    l.to_world = scene.luminaires[i].to_world;
    l.intensity = scene.luminaires[i].intensity;
    l.prepare();
    lights.push_back(l);
  }
  return lights;
}

}  // namespace nf::render
