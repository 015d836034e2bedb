#include "render/reference_run.h"

#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/timer.h"
#include "reference/cache_key.h"
#include "render/reference_lights.h"

namespace nf::render {

namespace {

// The scene's luminaires, and the last scene's kept for the next call with the same content
// (scene text, the contents of its files, camera; reference/cache_key.h) and load options:
// `nearfield serve` renders many parts of one scene in one process (docs/cluster.md, "Per-part
// cost"). Generating and precomputing is deterministic, so the reuse changes no bit.
std::shared_ptr<const LuminaireSet> scene_luminaires(const scene::Scene& scene, const std::string& name,
                                                     const LuminaireLoadOptions& load) {
  static std::mutex mutex;
  static std::string last_key;
  static std::shared_ptr<const LuminaireSet> last;
  const std::string key = fmt::format("{} {} {}", ref::content_key(scene, ref::ReferenceSettings{}),
                                      load.preset_resolution_scale, load.threads);
  std::lock_guard<std::mutex> lock(mutex);
  if (last && key == last_key) return last;
  last.reset();  // one set at a time
  last = std::make_shared<const LuminaireSet>(load_luminaires(scene.luminaires, name, load));
  last_key = key;
  return last;
}

// Loads the scene's luminaires and environment and calls render(lights, environment); returns the
// loading time in ms.
template <typename Render>
double with_lights(const scene::Scene& scene, const LuminaireLoadOptions& load, Render render) {
  Timer t;
  const std::string name = scene.file.empty() ? std::string("scene") : scene.file.string();
  const std::shared_ptr<const LuminaireSet> kept = scene_luminaires(scene, name, load);
  const LuminaireSet& set = *kept;
  const std::vector<ref::LightFieldLight> lights = reference_lights(scene, set);
  std::unique_ptr<ref::EnvironmentMap> env;
  if (scene.environment) {
    try {
      env = std::make_unique<ref::EnvironmentMap>(ref::EnvironmentMap::load(
          scene.environment->file, scene.environment->rotation_deg, scene.environment->intensity));
    } catch (const Error& e) {
      fail(fmt::format("{}: /environment: {}", name, e.what()));
    }
  }
  const double load_ms = t.ms();
  render(lights, env.get());
  return load_ms;
}

}  // namespace

ReferenceRun run_reference(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                           const LuminaireLoadOptions& load) {
  settings.validate(scene.environment.has_value());
  ReferenceRun run;
  run.key = ref::cache_key(scene, settings);
  run.load_ms = with_lights(scene, load, [&](const auto& lights, const ref::EnvironmentMap* env) {
    run.result = ref::render_reference(scene, lights, env, settings);
  });
  return run;
}

ReferencePartRun run_reference_part(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                                    const ref::ImageRegion& region, const LuminaireLoadOptions& load) {
  settings.validate(scene.environment.has_value());
  region.validate(scene.camera.width, scene.camera.height, settings.spp);
  ReferencePartRun run;
  run.content_key = ref::content_key(scene, settings);
  run.load_ms = with_lights(scene, load, [&](const auto& lights, const ref::EnvironmentMap* env) {
    run.part = ref::render_reference_part(scene, lights, env, settings, region);
  });
  return run;
}

namespace {

constexpr const char* kDescription = "nearfield:reference_description";

// Reads one cached file if its description matches (`channels` channels).
bool read_matching(const std::filesystem::path& file, const std::string& description, Image& img,
                   ImageAttributes& attrs) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return false;
  img = read_image(file, &attrs);
  for (const auto& [k, v] : attrs)
    if (k == kDescription) return v == description && img.channels >= 3;
  return false;
}

// The image (RGB) and its companion <name>-aux.exr (R = variance of the mean luminance, G = kind).
bool load_cached(const std::filesystem::path& file, const std::filesystem::path& aux_file,
                 const std::string& description, ReferenceRun& run) {
  try {
    Image img, aux;
    ImageAttributes attrs, aux_attrs;
    if (!read_matching(file, description, img, attrs) || !read_matching(aux_file, description, aux, aux_attrs))
      return false;
    if (aux.width != img.width || aux.height != img.height) return false;
    const int w = img.width, h = img.height;
    run.result.image = Image(w, h, 3);
    run.result.variance = Image(w, h, 1);
    run.result.kinds.assign(static_cast<std::size_t>(w) * h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) run.result.image.at(x, y, c) = img.at(x, y, c);
        run.result.variance.at(x, y, 0) = aux.at(x, y, 0);
        run.result.kinds[static_cast<std::size_t>(y) * w + x] = static_cast<std::uint8_t>(aux.at(x, y, 1));
      }
    for (const auto& [k, v] : attrs) {
      if (k == "nearfield:render_ms") run.result.stats.render_ms = std::stod(v);
      if (k == "nearfield:rays") run.result.stats.camera_rays = std::stoull(v);
    }
    run.from_cache = true;
    return true;
  } catch (const std::exception&) {
    return false;  // unreadable: render it again
  }
}

}  // namespace

ReferenceRun cached_reference(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                              const std::filesystem::path& cache_dir, const std::string& prefix, bool refresh,
                              const LuminaireLoadOptions& load) {
  const std::string description = ref::cache_description(scene, settings);
  const std::string key = ref::cache_key(scene, settings);
  const std::filesystem::path file = cache_dir / fmt::format("{}-{}.exr", prefix, key);
  const std::filesystem::path aux_file = cache_dir / fmt::format("{}-{}-aux.exr", prefix, key);
  ReferenceRun run;
  run.key = key;
  if (!refresh && load_cached(file, aux_file, description, run)) return run;
  run = run_reference(scene, settings, load);
  std::filesystem::create_directories(cache_dir);
  const auto& r = run.result;
  Image aux(r.image.width, r.image.height, 3);
  for (int y = 0; y < aux.height; ++y)
    for (int x = 0; x < aux.width; ++x) {
      aux.at(x, y, 0) = r.variance.at(x, y, 0);
      aux.at(x, y, 1) = r.kinds[static_cast<std::size_t>(y) * aux.width + x];
    }
  const ImageAttributes attrs{{kDescription, description},
                              {"nearfield:render_ms", fmt::format("{:.3f}", r.stats.render_ms)},
                              {"nearfield:rays", std::to_string(r.stats.rays())}};
  OutputTransaction tx;  // the image and its aux file together, or neither
  write_exr(tx, file, r.image, attrs);
  write_exr(tx, aux_file, aux, attrs);
  tx.commit();
  return run;
}

}  // namespace nf::render
