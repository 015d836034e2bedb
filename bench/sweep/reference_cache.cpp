#include "bench/sweep/reference_cache.h"

#include <fmt/format.h>
#include <chrono>
#include <ctime>

#include "bench/sweep/hash.h"
#include "cl/runtime.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/timer.h"
#include "gl/shader.h"

namespace nf::bench {
namespace {

namespace fs = std::filesystem;

// Bump when the meaning of a cached file changes (layout, estimator definition).
constexpr int kCacheVersion = 1;

std::string attr(const ImageAttributes& a, const std::string& key) {
  for (const auto& [k, v] : a)
    if (k == key) return v;
  return {};
}

double noise_rel_mse(const Reference& r) {
  if (r.even.pixels.size() != r.image.pixels.size()) return 0.0;
  double num = 0, den = 0;
  const std::size_t n = r.valid.size();
  for (std::size_t p = 0; p < n; ++p) {
    if (!r.valid[p]) continue;
    for (int c = 0; c < 3; ++c) {
      const double full = r.image.pixels[p * 3 + c], even = r.even.pixels[p * 3 + c];
      const double odd = 2.0 * full - even;  // an even number of frames: full = (even + odd) / 2
      num += (even - odd) * (even - odd);
      den += full * full;
    }
  }
  return den > 0 ? num / 4.0 / den : 0.0;
}

bool load(const fs::path& file, const fs::path& even_file, const std::string& description, Reference& r) {
  if (!fs::exists(file) || !fs::exists(even_file)) return false;
  try {
    ImageAttributes a;
    const Image rgba = read_image(file, &a);
    if (attr(a, "nearfield:bench_reference") != description || rgba.channels != 4) {
      log::info("reference cache: {} does not match the current settings; recomputing", file.string());
      return false;
    }
    const Image even = read_image(even_file);
    if (even.width != rgba.width || even.height != rgba.height || even.channels != 3) return false;
    const std::size_t n = static_cast<std::size_t>(rgba.width) * rgba.height;
    r.image = Image(rgba.width, rgba.height, 3);
    r.valid.assign(n, 0);
    for (std::size_t p = 0; p < n; ++p) {
      for (int c = 0; c < 3; ++c) r.image.pixels[p * 3 + c] = rgba.pixels[p * 4 + c];
      r.valid[p] = rgba.pixels[p * 4 + 3] > 0.5f ? 1 : 0;
    }
    r.even = even;
    r.render_ms = std::atof(attr(a, "nearfield:render_ms").c_str());
    r.samples = std::strtoull(attr(a, "nearfield:samples").c_str(), nullptr, 10);
    return true;
  } catch (const std::exception& e) {
    log::warn("reference cache: {}: {}; recomputing", file.string(), e.what());
    return false;
  }
}

// The estimator code a reference depends on: the OpenCL kernels, and for scenes the GL shaders of
// Step 0. A change to either recomputes the references (a bug fix there may change the truth).
std::string code_fingerprint(const Target& target) {
  Fnv64 k;
  k.add(cl::kernel_source("lightfield.cl"));
  std::string out = "kernels=" + k.hex();
  if (target.kind() == "scene") {
    Fnv64 g;
    for (const auto& f : gl::embedded_shader_files()) {
      g.add(f.path);
      g.add(f.text);
    }
    out += " shaders=" + g.hex();
  }
  return out;
}

}  // namespace

render::SamplingSettings ReferenceSpec::settings() const {
  render::SamplingSettings s;
  s.method = render::Method::ours;
  s.sampler = render::SamplerKind::random;
  s.balance = render::Balance::roulette;
  s.search = render::SearchKind::secant;
  s.search_depth = -1;
  s.structure = render::Structure::fused;
  s.spp = spp_per_frame;
  s.k_max = 0;
  s.seed = seed;
  s.frame = 0;
  return s;
}

Reference get_reference(Target& target, const ReferenceSpec& spec, const fs::path& cache_dir, bool refresh) {
  if (spec.frames < 2 || spec.frames % 2)
    fail(fmt::format("reference: frames must be even and >= 2, got {}", spec.frames));
  const render::SamplingSettings s = spec.settings();
  const std::string description = fmt::format("v{} {} | {} | {} band={} | frames={}", kCacheVersion, target.describe(),
                                              code_fingerprint(target), s.describe(), s.band, spec.frames);
  Reference r;
  r.key = fnv_hex(description);
  r.spp = spec.spp();
  r.file = cache_dir / fmt::format("{}-{}.exr", target.name(), r.key);
  const fs::path even_file = cache_dir / fmt::format("{}-{}-even.exr", target.name(), r.key);
  if (!refresh && load(r.file, even_file, description, r)) {
    r.from_cache = true;
    r.noise_rel_mse = noise_rel_mse(r);
    log::info("reference {}: cached {} ({} spp)", target.name(), r.file.string(), r.spp);
    return r;
  }
  fs::create_directories(cache_dir);
  Progress progress(fmt::format("reference {} ({} spp)", target.name(), r.spp), static_cast<std::size_t>(spec.frames),
                    0.0);
  Timer t;
  Rendering out = target.render(s, spec.frames, [&] { progress.advance(); });
  progress.finish();
  r.render_ms = t.ms();
  r.samples = out.samples;
  r.image = std::move(out.image);
  r.even = std::move(out.even);
  r.valid = std::move(out.valid);
  r.noise_rel_mse = noise_rel_mse(r);

  Image rgba(r.image.width, r.image.height, 4);
  const std::size_t n = r.valid.size();
  for (std::size_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) rgba.pixels[p * 4 + c] = r.image.pixels[p * 3 + c];
    rgba.pixels[p * 4 + 3] = r.valid[p] ? 1.0f : 0.0f;
  }
  const ImageAttributes a{{"nearfield:bench_reference", description},
                          {"nearfield:render_ms", fmt::format("{:.1f}", r.render_ms)},
                          {"nearfield:samples", std::to_string(r.samples)},
                          {"nearfield:spp", std::to_string(r.spp)},
                          {"nearfield:date", utc_now()}};
  write_exr(even_file, r.even, {{"nearfield:bench_reference", description}});
  write_exr(r.file, rgba, a);  // last: its presence marks a complete pair
  log::info("reference {}: {} spp in {:.1f} s -> {}", target.name(), r.spp, r.render_ms / 1e3, r.file.string());
  return r;
}

}  // namespace nf::bench
