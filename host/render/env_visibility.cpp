#include "render/env_visibility.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "core/timer.h"
#include "gl/env_shadow_maps.h"

namespace nf::render {
namespace {

double radical_inverse2(std::uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return static_cast<double>(i) * (1.0 / 4294967296.0);
}

cl_float4 f4(const glm::dvec3& v, double w = 0.0) {
  return cl_float4{{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), static_cast<float>(w)}};
}

}  // namespace

// Deterministic env-map importance sampling (Krivanek and Colbert 2008 §5.2): Hammersley point i
// of n, (u0, u1) = ((i + 1/2) / n, radical inverse of i), through the map's marginal and
// conditional CDFs (the tables env-is samples from), so the maps sit where the map is bright.
std::vector<glm::dvec3> env_visibility_directions(const ref::EnvironmentMap& map, int n) {
  std::vector<glm::dvec3> out;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    const double u0 = std::min((i + 0.5) / n, 1.0 - 1e-12), u1 = radical_inverse2(static_cast<std::uint32_t>(i));
    const ref::EnvironmentMap::Sample s = map.empty() ? ref::EnvironmentMap::Sample{} : map.sample(u0, u1);
    if (s.pdf > 0.0) {
      out.push_back(glm::normalize(s.direction));
    } else {  // all-black map: nothing to weight by, use the points uniformly on the sphere
      const double z = 1.0 - 2.0 * u0, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * pi * u1;
      out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return out;
}

EnvVisibility::EnvVisibility(cl::Runtime& rt) : rt_(rt) {
  const std::vector<cl_float4> zeros(16, cl_float4{{0, 0, 0, 0}});
  off_args_ = cl::upload(rt_, zeros, "environment visibility: arguments when off");
}

EnvVisibility::~EnvVisibility() = default;

// L_k = int L_env Y_k dw by the texel sum of env_sh16_rows (rows summed here in double).
void EnvVisibility::project(const ref::EnvironmentMap& map, const ::cl::Buffer& pyr, const ::cl::Buffer& lv) {
  const int h = map.height();
  // env_sh16_rows(pyr, lv, rot, out)
  cl::TypedKernel<::cl::Buffer, ::cl::Buffer, cl_float2, ::cl::Buffer> k(rt_, "env_visibility.cl", "env_sh16_rows");
  ::cl::Buffer rows;
  cl::call(
      [&] { rows = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, sizeof(float) * 48 * static_cast<std::size_t>(h)); },
      "environment order-4 SH buffer");
  k.bind(pyr, lv, cl_float2{{static_cast<float>(map.rotation_cos()), static_cast<float>(map.rotation_sin())}}, rows);
  rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(h)));
  std::vector<float> part(48 * static_cast<std::size_t>(h));
  cl::call([&] { rt_.queue().enqueueReadBuffer(rows, CL_TRUE, 0, part.size() * sizeof(float), part.data()); },
           "reading the environment order-4 SH rows");
  lsh_.fill(glm::dvec3(0.0));
  for (std::size_t r = 0; r < static_cast<std::size_t>(h); ++r)
    for (std::size_t j = 0; j < 16; ++j)
      for (int c = 0; c < 3; ++c) lsh_[j][c] += part[48 * r + 3 * j + static_cast<std::size_t>(c)];
  std::vector<cl_float4> l4;
  for (const auto& v : lsh_) l4.push_back(f4(v));
  lsh_buf_ = cl::upload(rt_, l4, "uploading the environment order-4 SH");
  projected_ = true;
}

void EnvVisibility::prepare(const FrameInputs& in) {
  if (scene::choice_value<scene::EnvVisibilityKind>(in.settings.declared.env_visibility) !=
      scene::EnvVisibilityKind::sh)
    return;
  if (!fit_) fit_ = {rt_, "env_visibility.cl", "env_vis_fit"};
  if (!projected_) (void)rt_.kernel("env_visibility.cl", "env_sh16_rows");
}

EnvVisibility::Frame EnvVisibility::run(const FrameInputs& in, const ref::EnvironmentMap& map, const ::cl::Buffer& pyr,
                                        const ::cl::Buffer& lv) {
  Frame f;
  f.coeffs = f.lsh = &off_args_;
  const auto& d = in.settings.declared;
  if (scene::choice_value<scene::EnvVisibilityKind>(d.env_visibility) != scene::EnvVisibilityKind::sh) return f;
  if (!in.scene_gpu || !in.geometry)
    fail("env_visibility sh: needs the scene's geometry on the GPU (render it through the frame's Renderer)");
  const int n = d.env_visibility_samples, size = in.settings.shadow_map_size;
  scene::check_setting(d, "env_visibility_samples", "environment");
  const double map_bytes = static_cast<double>(n) * size * size * sizeof(float);
  if (map_bytes > 1024.0 * 1024.0 * 1024.0)
    fail(
        fmt::format("env_visibility: {} shadow maps of {}^2 floats need {:.0f} MiB (limit 1024); lower "
                    "env_visibility_samples or shadow_map_size",
                    n, size, map_bytes / (1024.0 * 1024.0)));
  Timer build;
  bool built = false;
  if (!projected_) {
    project(map, pyr, lv);
    built = true;
  }
  if (!maps_ || built_for_ != in.scene_gpu || built_n_ != n || built_size_ != size) {
    dirs_ = env_visibility_directions(map, n);
    pinv_ = sh16_pseudoinverse(dirs_);
    glm::dvec3 lo, hi;
    in.geometry->bounds(lo, hi);
    maps_ = std::make_unique<gl::EnvShadowMaps>(dirs_, lo, hi, size);
    maps_->render(*in.scene_gpu);
    maps_buf_ = cl::upload(rt_, maps_->maps(), "uploading the environment shadow maps");
    std::vector<cl_float4> frames;
    for (const auto& fr : maps_->frames()) {
      frames.push_back(f4(fr.e1));
      frames.push_back(f4(fr.e2));
      frames.push_back(f4(fr.w));
    }
    frames_buf_ = cl::upload(rt_, frames, "uploading the environment shadow-map frames");
    std::vector<float> p(pinv_.p.begin(), pinv_.p.end());
    pinv_buf_ = cl::upload(rt_, p, "uploading the SH pseudoinverse");
    built_for_ = in.scene_gpu;
    built_n_ = n;
    built_size_ = size;
    bytes_ = maps_->maps().size() * sizeof(float) + frames.size() * sizeof(cl_float4) + p.size() * sizeof(float) +
             16 * sizeof(cl_float4);
    built = true;
    fitted_ = false;
  }
  if (built) f.build_ms = build.ms();
  f.coeffs = &coeffs_;
  f.lsh = &lsh_buf_;
  f.on = true;
  if (fitted_ && in.view_version != 0 && in.view_version == fitted_version_ && in.count == fitted_count_)
    return f;  // same surfaces, same maps: the coefficients are still valid
  if (!fit_) fit_ = {rt_, "env_visibility.cl", "env_vis_fit"};
  const std::size_t count = static_cast<std::size_t>(std::max(in.count, 1));
  if (coeff_bytes_ != count * 4 * sizeof(cl_float4)) {
    cl::call([&] { coeffs_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, count * 4 * sizeof(cl_float4)); },
             "environment visibility coefficients buffer");
    coeff_bytes_ = count * 4 * sizeof(cl_float4);
  }
  // Biases (docs/env_visibility.md): normal offset 1.5 texels, depth bias 1 texel; a texel is 2R/size
  // metres, and one metre is 1/(2R) in depth units, so a texel is 1/size there.
  const double r = maps_->radius(), texel = 2.0 * r / size;
  fit_.bind(in.surfaces, in.count, maps_buf_, frames_buf_, maps_->count(), size, f4(maps_->centre(), r), pinv_buf_,
            cl_float2{{static_cast<float>(1.5 * texel), static_cast<float>(1.0 / size)}}, coeffs_);
  const ::cl::Event ev = rt_.launch(fit_.get(), ::cl::NDRange(count));
  cl::call([&] { ev.wait(); }, "environment visibility fit");
  f.fit_ms = cl::Runtime::event_ms(ev);
  fitted_ = true;
  fitted_version_ = in.view_version;
  fitted_count_ = in.count;
  return f;
}

std::vector<glm::vec4> EnvVisibility::read_coeffs(int count) {
  std::vector<glm::vec4> out(4 * static_cast<std::size_t>(std::max(count, 0)));
  if (out.empty() || coeff_bytes_ < out.size() * sizeof(glm::vec4)) return {};
  cl::call([&] { rt_.queue().enqueueReadBuffer(coeffs_, CL_TRUE, 0, out.size() * sizeof(glm::vec4), out.data()); },
           "reading the environment visibility coefficients");
  return out;
}

}  // namespace nf::render
