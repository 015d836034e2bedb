#include "app/render_estimate.h"

#include <algorithm>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "core/error.h"
#include "core/image_io.h"
#include "core/memory.h"
#include "luminaire/generator.h"
#include "luminaire/io.h"
#include "luminaire/memory_estimate.h"
#include "render/environment_contribution.h"
#include "render/farfield_contribution.h"
#include "render/kurt_table.h"
#include "kernels/shared/sampling.h"
#include "render/luminaire_cache.h"
#include "render/settings.h"

namespace nf::app {

RenderEstimate estimate_render(const scene::Scene& s) {
  RenderEstimate e;
  const std::uint64_t pixels = static_cast<std::uint64_t>(s.camera.width) * static_cast<std::uint64_t>(s.camera.height);
  e.per_pixel = mul_sat(pixels, kHostBytesPerPixel + kDeviceBytesPerPixel);  // both sides, for display
  std::set<std::string> seen;  // instances of one luminaire share its device data (render/luminaire_cache.h)
  for (std::size_t i = 0; i < s.luminaires.size(); ++i) {
    const auto& l = s.luminaires[i];
    if (l.manifest.empty() || !seen.insert(render::luminaire_key(l)).second) continue;
    lum::LuminaireMemory m;
    try {  // name the scene and the instance, as loading the luminaire does
      m = lum::estimate_memory(lum::read_manifest(l.manifest), 3);
    } catch (const Error& err) {
      fail(fmt::format("{}: /luminaires/{} ('{}'): {}", s.file.string(), i, l.name, err.what()));
    }
    e.luminaires_host = add_sat(e.luminaires_host, m.host());
    e.luminaires_device = add_sat(e.luminaires_device, m.device());
  }
  if (s.needs_shadow_maps()) {  // docs/rendering.md "Shadow maps at scale": every instance exact (the worst case)
    const std::uint64_t texels =
        static_cast<std::uint64_t>(s.render.shadow_map_size) * static_cast<std::uint64_t>(s.render.shadow_map_size);
    for (std::size_t i = 0; i < s.luminaires.size(); ++i) {
      const auto& l = s.luminaires[i];
      lum::Basis basis;
      try {
        basis = l.manifest.empty() ? lum::preset_basis(l.preset) : lum::read_manifest(l.manifest).basis;
      } catch (const Error& err) {
        fail(fmt::format("{}: /luminaires/{} ('{}'): {}", s.file.string(), i, l.name, err.what()));
      }
      const std::uint64_t cells = static_cast<std::uint64_t>(basis.count[0] + basis.support() - 1) *
                                  static_cast<std::uint64_t>(basis.count[1] + basis.support() - 1);
      const std::uint64_t maps = add_sat(mul_sat(mul_sat(cells, texels), 4), add_sat(texels * 4, cells * 16));
      const std::uint64_t bitmask = mul_sat(pixels, ((cells + 31) / 32) * 4);
      // GL (llvmpipe: host memory): maps, depth target, lights, the bitmask's buffer and its
      // readback; the OpenCL pass keeps a copy of the maps on the device; the bitmask is uploaded.
      e.shadow_maps_host = add_sat(e.shadow_maps_host, add_sat(maps, mul_sat(bitmask, 2)));
      e.shadow_maps_device = add_sat(
          e.shadow_maps_device,
          add_sat(scene::choice_value<scene::VisibilityPass>(s.render.visibility_pass) == scene::VisibilityPass::gl
                      ? 0
                      : maps,
                  bitmask));
    }
  }
  const bool paraboloid = scene::choice_value<scene::EnvParam>(s.render.env_param) == scene::EnvParam::paraboloid;
  const std::size_t kurt_entries = s.geometry.materials.size();  // render::kurt_table: one entry per material
  const auto n = static_cast<std::size_t>(pixels);
  if (s.environment) {
    std::pair<int, int> wh;
    try {
      wh = read_image_size(s.environment->file);
    } catch (const Error& err) {
      fail(fmt::format("{}: /environment: {}", s.file.string(), err.what()));
    }
    const std::uint64_t texels = static_cast<std::uint64_t>(wh.first) * static_cast<std::uint64_t>(wh.second);
    e.environment_host = mul_sat(texels, kEnvironmentHostBytesPerTexel);
    // env_diffuse sh without SH visibility shades the map's brightest blocks as lights
    const bool sh_lights = scene::choice_value<scene::EnvDiffuse>(s.render.env_diffuse) == scene::EnvDiffuse::sh &&
                           scene::choice_value<scene::EnvVisibilityKind>(s.render.env_visibility) ==
                               scene::EnvVisibilityKind::none;
    e.environment_device = render::EnvironmentContribution::estimate_bytes(wh.first, wh.second, paraboloid, n,
                                                                           sh_lights ? s.render.env_sh_lights : 0) +
                           render::kurt_table_bytes(kurt_entries);
  }
  if (!s.farfield_lights.empty())
    e.farfield_device =
        render::FarfieldContribution::estimate_bytes(s.farfield_lights, n, s.needs_shadow_maps(), kurt_entries);
  for (const auto& local : s.local_environments) {
    const std::uint64_t texels = static_cast<std::uint64_t>(local.size) * static_cast<std::uint64_t>(local.size / 2);
    e.local_host = add_sat(e.local_host, mul_sat(texels, kEnvironmentHostBytesPerTexel));
    e.local_device = add_sat(
        e.local_device, render::EnvironmentContribution::estimate_local_bytes(local.size, paraboloid, n, kurt_entries));
  }
  if (!s.local_environments.empty() && !s.environment)  // the far pass still runs, on a black 2 x 1 map
    e.local_device = add_sat(e.local_device, render::EnvironmentContribution::estimate_bytes(2, 1, paraboloid, n) +
                                                 render::kurt_table_bytes(kurt_entries));
  e.geometry = mul_sat(scene::count(s).triangles, kBytesPerTriangle);
  e.host = add_sat(
      add_sat(add_sat(add_sat(mul_sat(pixels, kHostBytesPerPixel), e.luminaires_host), e.geometry), e.environment_host),
      add_sat(e.local_host, e.shadow_maps_host));
  e.device =
      add_sat(add_sat(add_sat(add_sat(add_sat(mul_sat(pixels, kDeviceBytesPerPixel), e.luminaires_device), e.geometry),
                              e.environment_device),
                      e.farfield_device),
              add_sat(e.local_device, e.shadow_maps_device));
  return e;
}

std::vector<InstanceCost> instance_costs(const scene::Scene& s) {
  std::vector<InstanceCost> out;
  std::vector<std::string> keys;
  std::vector<lum::Luminaire> lums;
  for (std::size_t i = 0; i < s.luminaires.size(); ++i) {
    const auto& ref = s.luminaires[i];
    const std::string key = render::luminaire_key(ref);
    const auto it = std::find(keys.begin(), keys.end(), key);
    if (it != keys.end()) {
      ++out[static_cast<std::size_t>(it - keys.begin())].instances;
      continue;
    }
    try {
      lums.push_back(ref.preset.empty() ? lum::read_manifest(ref.manifest)
                                        : lum::generate_preset(ref.preset, lum::GenOptions{0.02, 1}));
    } catch (const Error& err) {
      fail(fmt::format("{}: /luminaires/{} ('{}'): {}", s.file.string(), i, ref.name, err.what()));
    }
    keys.push_back(key);
    out.push_back({ref.preset.empty() ? ref.manifest.string() : ref.preset + " (preset)", 1, {}});
  }
  const std::uint64_t pixels = static_cast<std::uint64_t>(s.camera.width) * static_cast<std::uint64_t>(s.camera.height);
  const std::size_t n = s.luminaires.size() + 1;  // with the one more instance
  const bool all =
      !render::selects_instances(render::parse_light_selection(s.render.light_selection), n, s.farfield_lights.size());
  // every instance's pixel cache, the one more included (the cache holds all or none); with light
  // selection by image pixel, one more row, and none when a luminaire has more than NF_FUSED_CACHE images
  std::uint64_t cache = 0;
  bool cacheable = s.render.pixel_cache > 0;
  for (std::size_t k = 0; k < lums.size(); ++k) {
    cache += 4ULL * static_cast<std::uint64_t>(lums[k].num_images() + (all ? 0 : 1)) * pixels *
             (out[k].instances + (k == 0 ? 1 : 0));
    cacheable = cacheable && (all || lums[k].num_images() <= NF_FUSED_CACHE);
  }
  const bool cache_on = cacheable && cache <= (static_cast<std::uint64_t>(s.render.pixel_cache) << 20);
  for (std::size_t k = 0; k < lums.size(); ++k)
    out[k].more = render::instance_device_bytes(lums[k], pixels, cache_on,
                                                s.needs_shadow_maps() ? s.render.shadow_map_size : 0, !all);
  return out;
}

void check_render_memory(const std::string& where, const RenderEstimate& e, const cl::DeviceInfo& device) {
  const bool shared = device.type == "CPU";
  const std::uint64_t host_need = shared ? add_sat(e.host, e.device) : e.host;
  check_memory(where, "rendering this scene (image, luminaires, geometry)", host_need, available_host_memory(),
               shared ? "host memory (shared with the OpenCL CPU device)" : "host memory");
  if (!shared)
    check_memory(where, "rendering this scene on the OpenCL device", e.device,
                 static_cast<std::uint64_t>(device.global_mem_bytes), "device memory on " + device.name);
}

}  // namespace nf::app
