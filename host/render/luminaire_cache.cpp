#include "render/luminaire_cache.h"

#include <fmt/format.h>

#include <filesystem>
#include <map>

#include "core/error.h"
#include "core/timer.h"
#include "luminaire/generator.h"
#include "luminaire/io.h"
#include "luminaire/precompute.h"

namespace nf::render {

std::string luminaire_key(const scene::LuminaireRef& ref) {
  if (!ref.preset.empty()) return "preset:" + ref.preset;
  std::error_code ec;
  const auto canonical = std::filesystem::weakly_canonical(ref.manifest, ec);
  return ec ? ref.manifest.lexically_normal().string() : canonical.string();
}

namespace {

LuminaireSource load_source(const scene::LuminaireRef& ref, const LuminaireLoadOptions& options) {
  LuminaireSource src;
  src.key = luminaire_key(ref);
  Timer t;
  if (!ref.preset.empty()) {
    lum::GenOptions gen;
    gen.resolution_scale = options.preset_resolution_scale;
    gen.threads = options.threads;
    src.label = ref.preset + " (preset)";
    src.luminaire = lum::generate_preset(ref.preset, gen);
  } else {
    src.label = ref.manifest.string();
    src.luminaire = lum::read_luminaire(ref.manifest);
  }
  src.load_ms = t.ms();
  src.precomputed = lum::precompute(src.luminaire, options.threads);
  return src;
}

}  // namespace

LuminaireSet load_luminaires(const std::vector<scene::LuminaireRef>& refs, const std::string& scene_name,
                             const LuminaireLoadOptions& options) {
  LuminaireSet set;
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    const std::string key = luminaire_key(refs[i]);
    auto it = index.find(key);
    if (it == index.end()) {
      try {
        set.sources.push_back(load_source(refs[i], options));
      } catch (const Error& e) {
        fail(fmt::format("{}: /luminaires/{} ('{}'): {}", scene_name, i, refs[i].name, e.what()));
      }
      it = index.emplace(key, set.sources.size() - 1).first;
    }
    set.sources[it->second].instances.push_back(i);
    set.source_of.push_back(it->second);
  }
  return set;
}

}  // namespace nf::render
