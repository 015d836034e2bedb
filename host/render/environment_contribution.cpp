#include "render/environment_contribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/timer.h"
#include "reference/ray_scene.h"
#include "render/kurt_table.h"
#include "render/local_environment.h"
#include "render/regular_pattern.h"

namespace nf::render {
namespace {

using scene::EnvFilter;
using scene::EnvGlossy;
using scene::EnvParam;

// The kernel codes of the typed choices (environment.cl NF_ENV_GLOSSY, env_pyramid's filter).
int glossy_index(EnvGlossy g) {
  switch (g) {
    case EnvGlossy::mc:
      return 0;
    case EnvGlossy::fis:
      return 1;
    case EnvGlossy::fis_rotated:
      return 2;
    case EnvGlossy::env_is:
      return 3;
    case EnvGlossy::env_fis:
      return 4;
    case EnvGlossy::regular:
      return 5;
  }
  return 0;
}

int filter_index(EnvFilter f) {
  switch (f) {
    case EnvFilter::box:
      return 0;
    case EnvFilter::gauss4:
      return 1;
    case EnvFilter::gauss6:
      return 2;
  }
  return 0;
}

// Level sizes from (w, h) down to the top: halved (rounded down, at least 1) until 1 x 1 for the
// lat-long pyramid; for the paraboloid one (2 S, S) with S halved until 1.
std::vector<glm::ivec2> level_dims(glm::ivec2 d, bool paraboloid) {
  std::vector<glm::ivec2> dims;
  for (;;) {
    dims.push_back(d);
    if (paraboloid ? d.y == 1 : (d.x == 1 && d.y == 1)) break;
    d = paraboloid ? glm::ivec2(2 * std::max(1, d.y / 2), std::max(1, d.y / 2))
                   : glm::ivec2(std::max(1, d.x / 2), std::max(1, d.y / 2));
  }
  return dims;
}

std::size_t texel_count(const std::vector<glm::ivec2>& dims) {
  std::size_t n = 0;
  for (const auto& d : dims) n += static_cast<std::size_t>(d.x) * static_cast<std::size_t>(d.y);
  return n;
}

}  // namespace

// One object's local map (docs/local-environment.md): its builder, the built map's own
// environment contribution (pyramids, SH, sampling tables) and the object's camera pixels.
struct EnvironmentContribution::Local {
  std::unique_ptr<LocalEnvironmentMap> builder;
  std::unique_ptr<EnvironmentContribution> env;
  InputKey key;  // what `env` was built for (LocalEnvironmentMap::key); empty: nothing built
  int builds = 0;
  LocalEnvironmentMap::Times times;  // of the last build
  double pixels_ms = 0.0;            // the last search for the object's camera pixels
  std::uint64_t pixels_version = 0;
  int pixels_count = -1;
  std::vector<std::uint8_t> pixels;  // 1: the object's camera pixel
  bool any = false;
  ::cl::Buffer masked;  // the camera's surfaces with every other pixel invalid
};

EnvironmentContribution::EnvironmentContribution(cl::Runtime& rt, const scene::Environment& env,
                                                 const std::vector<scene::Material>& materials)
    : EnvironmentContribution(rt, ref::EnvironmentMap::load(env.file, env.rotation_deg, env.intensity)) {
  set_kurt_table(kurt_table(materials));
}

EnvironmentContribution::EnvironmentContribution(cl::Runtime& rt, ref::EnvironmentMap map)
    : rt_(rt), map_(std::move(map)), vis_(rt) {
  upload();
  build();
  set_kurt_table({});
}

namespace {
ref::EnvironmentMap black_map() {
  Image img(2, 1, 3);
  return ref::EnvironmentMap(img, 0.0, 1.0, "no environment");
}
}  // namespace

EnvironmentContribution::EnvironmentContribution(cl::Runtime& rt, const scene::Scene& scene)
    : EnvironmentContribution(
          rt, scene.environment ? ref::EnvironmentMap::load(scene.environment->file, scene.environment->rotation_deg,
                                                            scene.environment->intensity)
                                : black_map()) {
  has_far_ = scene.environment.has_value();
  materials_ = scene.geometry.materials;
  set_kurt_table(kurt_table(materials_));
  for (const auto& spec : scene.local_environments) {
    auto l = std::make_unique<Local>();
    l->builder = std::make_unique<LocalEnvironmentMap>(rt, scene.geometry, spec, materials_);
    locals_.push_back(std::move(l));
  }
}

EnvironmentContribution::~EnvironmentContribution() = default;

const ref::EnvironmentMap& EnvironmentContribution::local_map(std::size_t i) const {
  static const ref::EnvironmentMap none;
  const Local& l = *locals_.at(i);
  return l.env ? l.env->map() : none;
}
int EnvironmentContribution::local_builds(std::size_t i) const { return locals_.at(i)->builds; }
glm::dvec3 EnvironmentContribution::local_centre(std::size_t i) const { return locals_.at(i)->builder->centre(); }
const std::vector<std::uint8_t>& EnvironmentContribution::local_pixels(std::size_t i) const {
  return locals_.at(i)->pixels;
}

void EnvironmentContribution::set_materials(const std::vector<scene::Material>& materials) {
  materials_ = materials;
  set_kurt_table(kurt_table(materials_));
  for (auto& l : locals_) {
    l->builder->set_materials(materials_);
    l->key.clear();         // rebuild the map
    l->pixels_version = 0;  // re-read the surfaces (their material parameters) for `masked`
    l->pixels_count = -1;
  }
}

void EnvironmentContribution::set_kurt_table(const std::vector<NfKurtMaterial>& table) {
  kurt_ = cl::upload(rt_, table, "uploading the environment's kurt material table");
  kurt_count_ = static_cast<int>(table.size());
  kurt_host_ = table;
  regular_budget_ = -1;  // the patterns follow the table
}

void EnvironmentContribution::set_regular(int budget, double eps0) {
  if (budget == regular_budget_ && eps0 == regular_eps_) return;
  std::vector<cl_float4> pat, lob;
  regular_counts_.clear();
  auto add = [&](const RegularPattern& p, bool unit) {
    lob.push_back(cl_float4{{static_cast<float>(pat.size()), static_cast<float>(p.size()), 0.0f, 0.0f}});
    regular_counts_.push_back(p.size());
    for (const glm::dvec3& h : p.h) {
      if (unit) {  // (cos phi, sin phi, theta / theta_max): the kernel scales theta per pixel
        const double st = std::hypot(h.x, h.y), th = std::atan2(st, h.z);
        const double c = st > 0.0 ? h.x / st : 1.0, sn = st > 0.0 ? h.y / st : 0.0;
        pat.push_back(
            cl_float4{{static_cast<float>(c), static_cast<float>(sn), static_cast<float>(th / p.theta_max), 0.0f}});
      } else {
        pat.push_back(cl_float4{{static_cast<float>(h.x), static_cast<float>(h.y), static_cast<float>(h.z), 0.0f}});
      }
    }
  };
  auto clamp_m = [](float m) { return std::clamp(static_cast<double>(m), double(NF_KURT_MIN_M), 1.0); };
  for (const NfKurtMaterial& m : kurt_host_) {
    const int count = std::clamp(m.count, 0, NF_KURT_MAX_LOBES);
    double wsum = 0.0;
    std::array<double, NF_KURT_MAX_LOBES> w{};
    for (int j = 0; j < count; ++j) {
      const NfKurtLobe& l = m.lobe[j];
      w[static_cast<std::size_t>(j)] = std::max({0.0f, l.ks_r, l.ks_g, l.ks_b});
      wsum += w[static_cast<std::size_t>(j)];
    }
    for (int j = 0; j < NF_KURT_MAX_LOBES; ++j) {
      if (j >= count) {
        lob.push_back(cl_float4{{0, 0, 0, 0}});
        regular_counts_.push_back(0);
        continue;
      }
      const double share = wsum > 0.0 ? w[static_cast<std::size_t>(j)] / wsum : 1.0 / count;
      const int nj = std::max(1, static_cast<int>(std::lround(budget * share)));
      add(regular_pattern_for_budget(nj, eps0, clamp_m(m.lobe[j].mx), clamp_m(m.lobe[j].my)), false);
    }
  }
  add(regular_pattern_for_budget(budget, eps0, 1.0, 1.0), true);  // GGX, after the table
  rpat_ = cl::upload(rt_, pat, "uploading the regular sampling patterns");
  rlob_ = cl::upload(rt_, lob, "uploading the regular sampling pattern table");
  regular_bytes_ = (pat.size() + lob.size()) * sizeof(cl_float4);
  regular_budget_ = budget;
  regular_eps_ = eps0;
}

int EnvironmentContribution::regular_samples(int material, int lobe) const {
  const std::size_t i =
      material < 0 ? regular_counts_.size() - 1 : static_cast<std::size_t>(material * NF_KURT_MAX_LOBES + lobe);
  return i < regular_counts_.size() ? regular_counts_[i] : 0;
}

double EnvironmentContribution::resolved_k(double env_k, EnvFilter filter) {
  if (env_k > 0.0) return env_k;
  return filter == EnvFilter::box ? 4.0 : 1.0;
}

std::size_t EnvironmentContribution::estimate_bytes(int width, int height, bool paraboloid, std::size_t pixels,
                                                    int sh_lights) {
  const std::size_t w = static_cast<std::size_t>(std::max(width, 1)), h = static_cast<std::size_t>(std::max(height, 1));
  const auto ll = level_dims(glm::ivec2(static_cast<int>(w), static_cast<int>(h)), false);
  std::size_t b = texel_count(ll) * 16 + ll.size() * 16;  // lat-long pyramid (float4) and its table
  b += (h + 1 + h * (w + 1) + w * h) * sizeof(float);     // row CDF, column CDFs, p_uv
  if (paraboloid) {
    const auto pl = level_dims(glm::ivec2(2 * static_cast<int>(h), static_cast<int>(h)), true);
    b += texel_count(pl) * 16 + pl.size() * 16;
  }
  // output radiance; the SH coefficients, the SH without its lights, and 2 float4 per light (at least
  // one: the dummy), as device_bytes() counts them (render/env_sh_lights.h: none under 64 rows)
  const std::size_t lights = height >= 64 ? static_cast<std::size_t>(std::clamp(sh_lights, 1, 128 * 64)) : 1;
  return b + pixels * 16 + 2 * 9 * 16 + 32 * lights;
}

std::size_t EnvironmentContribution::local_surface_bytes(std::size_t pixels) { return pixels * sizeof(NfSurface); }

std::size_t EnvironmentContribution::estimate_local_bytes(int size, bool paraboloid, std::size_t pixels,
                                                          std::size_t kurt_entries) {
  return estimate_bytes(size, size / 2, paraboloid, pixels) + kurt_table_bytes(kurt_entries) +
         local_surface_bytes(pixels);
}

// Level sizes: (W, H), then halved (rounded down, at least 1) until 1 x 1; all in one buffer.
void EnvironmentContribution::upload() {
  const int w = map_.width(), h = map_.height();
  dims_ = level_dims(glm::ivec2(w, h), false);
  offsets_.clear();
  int off = 0;
  for (const auto& d : dims_) {
    offsets_.push_back(off);
    off += d.x * d.y;
  }
  std::vector<cl_int4> lv;
  for (std::size_t k = 0; k < dims_.size(); ++k) lv.push_back(cl_int4{{offsets_[k], dims_[k].x, dims_[k].y, 0}});
  lv_ = cl::upload(rt_, lv, "uploading the environment pyramid levels");
  std::vector<cl_float4> all(static_cast<std::size_t>(off), cl_float4{{0, 0, 0, 0}});
  const auto& tex = map_.texels();
  // .w: the map-sampling density p_uv (env-fis integral kernel, Tokuyoshi 2016 Eq. 3)
  for (std::size_t i = 0; i < tex.size(); ++i)
    all[i] = cl_float4{{static_cast<float>(tex[i].x), static_cast<float>(tex[i].y), static_cast<float>(tex[i].z),
                        static_cast<float>(map_.texel_density_uv(i))}};
  pyr_ = cl::upload(rt_, all, "uploading the environment map");
  pyr_bytes_ = all.size() * sizeof(cl_float4) + lv.size() * sizeof(cl_int4);
  std::vector<float> rows(map_.row_cdf().begin(), map_.row_cdf().end());
  std::vector<float> cols(map_.col_cdf().begin(), map_.col_cdf().end());
  std::vector<float> puv(tex.size());
  for (std::size_t i = 0; i < tex.size(); ++i) puv[i] = static_cast<float>(map_.texel_density_uv(i));
  rows_ = cl::upload(rt_, rows, "uploading the environment row CDF");
  cols_ = cl::upload(rt_, cols, "uploading the environment column CDFs");
  puv_ = cl::upload(rt_, puv, "uploading the environment sampling density");
  table_bytes_ = (rows.size() + cols.size() + puv.size()) * sizeof(float);
}

// The pyramid (one env_pyramid_down launch per level) and the SH projection (env_sh_rows, rows
// summed here in double).
void EnvironmentContribution::build() {
  env_kernels::PyramidDown down(rt_, "environment.cl", "env_pyramid_down");  // compiled before the timer
  env_kernels::ShRows shk(rt_, "environment.cl", "env_sh_rows");
  Timer timer;
  for (std::size_t k = 0; k + 1 < dims_.size(); ++k) {
    down.bind(pyr_, lv_, static_cast<int>(k), filter_index(filter_), 0);
    const glm::ivec2 d = dims_[k + 1];
    rt_.launch(down.get(), ::cl::NDRange(static_cast<std::size_t>(d.x), static_cast<std::size_t>(d.y)));
  }
  cl::call([&] { rt_.queue().finish(); }, "building the environment pyramid");
  pyramid_ms_ = timer.ms();
  const int h = map_.height();
  ::cl::Buffer rows_out;
  cl::call([&] { rows_out = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, sizeof(float) * 27 * h); },
           "environment SH buffer");
  shk.bind(pyr_, lv_, cl_float2{{static_cast<float>(map_.rotation_cos()), static_cast<float>(map_.rotation_sin())}},
           rows_out);
  rt_.launch(shk.get(), ::cl::NDRange(static_cast<std::size_t>(h)));
  std::vector<float> part(static_cast<std::size_t>(27 * h));
  cl::call([&] { rt_.queue().enqueueReadBuffer(rows_out, CL_TRUE, 0, part.size() * sizeof(float), part.data()); },
           "reading the environment SH rows");
  sh_.fill(glm::dvec3(0.0));
  for (int r = 0; r < h; ++r)
    for (int k = 0; k < 9; ++k)
      for (int c = 0; c < 3; ++c)
        sh_[static_cast<std::size_t>(k)][c] += part[static_cast<std::size_t>(27 * r + 3 * k + c)];
  std::vector<cl_float4> shf;
  for (const auto& s : sh_)
    shf.push_back(cl_float4{{static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z), 0}});
  sh_buf_ = cl::upload(rt_, shf, "uploading the environment SH coefficients");
  sh_lights_ = brightest_blocks(map_, 256);
  shl_count_ = -1;
  if (param_ == EnvParam::paraboloid) build_paraboloid();
  build_ms_ = timer.ms();
}

// The dual-paraboloid pyramid (docs/environment.md, "Paraboloid"): level 0 (2 S) x S with S = H,
// resampled from the lat-long level 0 (env_paraboloid_base), then env_pyramid_down per level.
void EnvironmentContribution::build_paraboloid() {
  env_kernels::ParaboloidBase base(rt_, "environment.cl", "env_paraboloid_base");
  env_kernels::PyramidDown down(rt_, "environment.cl", "env_pyramid_down");
  Timer timer;
  pdims_ = level_dims(glm::ivec2(2 * map_.height(), map_.height()), true);
  poffsets_.clear();
  int off = 0;
  std::vector<cl_int4> lv;
  for (const auto& d : pdims_) {
    poffsets_.push_back(off);
    lv.push_back(cl_int4{{off, d.x, d.y, 0}});
    off += d.x * d.y;
  }
  plv_ = cl::upload(rt_, lv, "uploading the environment paraboloid levels");
  cl::call([&] { ppyr_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(off) * 16); },
           "environment paraboloid pyramid buffer");
  ppyr_bytes_ = static_cast<std::size_t>(off) * 16 + lv.size() * sizeof(cl_int4);
  base.bind(pyr_, lv_, ppyr_, plv_);
  rt_.launch(base.get(), ::cl::NDRange(static_cast<std::size_t>(pdims_[0].x), static_cast<std::size_t>(pdims_[0].y)));
  for (std::size_t k = 0; k + 1 < pdims_.size(); ++k) {
    down.bind(ppyr_, plv_, static_cast<int>(k), filter_index(filter_), 1);
    const glm::ivec2 d = pdims_[k + 1];
    rt_.launch(down.get(), ::cl::NDRange(static_cast<std::size_t>(d.x), static_cast<std::size_t>(d.y)));
  }
  cl::call([&] { rt_.queue().finish(); }, "building the environment paraboloid pyramid");
  paraboloid_ms_ = timer.ms();
}

std::vector<glm::vec4> EnvironmentContribution::read_paraboloid_level(int k) {
  const glm::ivec2 d = paraboloid_level_size(k);
  std::vector<glm::vec4> out(static_cast<std::size_t>(d.x) * static_cast<std::size_t>(d.y));
  cl::call(
      [&] {
        rt_.queue().enqueueReadBuffer(ppyr_, CL_TRUE, poffsets_[static_cast<std::size_t>(k)] * sizeof(cl_float4),
                                      out.size() * sizeof(cl_float4), out.data());
      },
      "reading an environment paraboloid level");
  return out;
}

std::vector<float> EnvironmentContribution::integral_level_debug(const std::vector<glm::vec2>& uv, float target) {
  std::vector<float> out(uv.size());
  if (uv.empty()) return out;
  ::cl::Buffer in = cl::upload(rt_, uv, "environment debug points"), buf;
  cl::call([&] { buf = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, out.size() * sizeof(float)); },
           "environment level buffer");
  env_kernels::IntegralDebug k(rt_, "environment.cl", "env_integral_debug");
  k.bind(pyr_, lv_, levels(), in, static_cast<int>(uv.size()), target, buf);
  rt_.launch(k.get(), ::cl::NDRange(out.size()));
  cl::call([&] { rt_.queue().enqueueReadBuffer(buf, CL_TRUE, 0, out.size() * sizeof(float), out.data()); },
           "reading the environment levels");
  return out;
}

std::vector<glm::vec4> EnvironmentContribution::read_level(int k) {
  const glm::ivec2 d = level_size(k);
  std::vector<glm::vec4> out(static_cast<std::size_t>(d.x) * static_cast<std::size_t>(d.y));
  cl::call(
      [&] {
        rt_.queue().enqueueReadBuffer(pyr_, CL_TRUE, offsets_[static_cast<std::size_t>(k)] * sizeof(cl_float4),
                                      out.size() * sizeof(cl_float4), out.data());
      },
      "reading an environment pyramid level");
  return out;
}

std::vector<glm::vec4> EnvironmentContribution::sample_map_debug(int count, std::uint32_t seed) {
  std::vector<glm::vec4> out(static_cast<std::size_t>(std::max(count, 0)));
  if (out.empty()) return out;
  ::cl::Buffer buf;
  cl::call([&] { buf = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, out.size() * sizeof(cl_float4)); },
           "environment sample buffer");
  env_kernels::SampleDebug k(rt_, "environment.cl", "env_sample_debug");
  k.bind(rows_, cols_, puv_, lv_,
         cl_float2{{static_cast<float>(map_.rotation_cos()), static_cast<float>(map_.rotation_sin())}},
         static_cast<cl_uint>(seed), count, buf);
  rt_.launch(k.get(), ::cl::NDRange(out.size()));
  cl::call([&] { rt_.queue().enqueueReadBuffer(buf, CL_TRUE, 0, out.size() * sizeof(cl_float4), out.data()); },
           "reading the environment samples");
  return out;
}

void EnvironmentContribution::set_filter(const std::string& filter) {
  set_filter(scene::choice_value<EnvFilter>(filter, "env_filter"));
}

void EnvironmentContribution::set_filter(EnvFilter filter) {
  if (filter == filter_) return;
  filter_ = filter;
  build();
  build_reported_ = false;
}

void EnvironmentContribution::set_param(const std::string& param) {
  set_param(scene::choice_value<EnvParam>(param, "env_param"));
}

void EnvironmentContribution::set_param(EnvParam param) {
  if (param == param_) return;
  param_ = param;
  if (param_ == EnvParam::paraboloid) {  // built while in use only
    build_paraboloid();
    build_ms_ += paraboloid_ms_;
    build_reported_ = false;
  } else {
    pdims_.clear();
    ppyr_ = ::cl::Buffer();
    ppyr_bytes_ = 0;
  }
}

void EnvironmentContribution::prepare(const FrameInputs& in) {
  const auto& d = in.settings.declared;
  set_filter(d.env_filter);  // first: a new filter with a new parametrisation builds once
  set_param(d.env_param);
  const EnvGlossy glossy = scene::choice_value<EnvGlossy>(d.env_glossy);
  if (glossy == EnvGlossy::regular) {
    set_regular(d.env_samples, d.env_regular_eps);
  } else if (regular_bytes_ > 0) {  // patterns only while in use
    rpat_ = ::cl::Buffer();
    rlob_ = ::cl::Buffer();
    regular_bytes_ = 0;
    regular_budget_ = -1;
  }
  const auto options_for = [&](bool background, bool vis) {
    return fmt::format(
        "-DNF_ENV_GLOSSY={} -DNF_ENV_DIFFUSE={} -DNF_ENV_BACKGROUND={} -DNF_ENV_KERNEL={} -DNF_ENV_PARAM={} "
        "-DNF_ENV_VIS={}",
        glossy_index(glossy), scene::choice_value<scene::EnvDiffuse>(d.env_diffuse) == scene::EnvDiffuse::mc ? 1 : 0,
        background ? 1 : 0, scene::choice_value<scene::EnvKernel>(d.env_kernel) == scene::EnvKernel::integral ? 1 : 0,
        param_ == EnvParam::paraboloid ? 1 : 0, vis ? 1 : 0);
  };
  const std::string options =
      options_for(scene::choice_value<scene::EnvBackground>(d.env_background) != scene::EnvBackground::hide,
                  scene::choice_value<scene::EnvVisibilityKind>(d.env_visibility) == scene::EnvVisibilityKind::sh);
  if (options != options_ || !shade_) {
    shade_ = env_kernels::Shade(rt_, "environment.cl", "env_shade", options);
    options_ = options;
  }
  // the local maps' passes (texels, the objects' pixels: no background, no far visibility) are
  // compiled here too, so that no frame's times include a compiler run
  if (!locals_.empty()) (void)rt_.program("environment.cl", options_for(false, false));
  vis_.prepare(in);
}

// The frame: the far map on every surface, then each local map on its object's pixels, which
// replace the far map's values there (docs/local-environment.md).
ContributionFrame EnvironmentContribution::add(const FrameInputs& in, std::vector<glm::vec4>& radiance) {
  ContributionFrame f;
  if (!build_reported_) {  // the one-time build shows in the first frame's first-pass time
    f.step1_ms = build_ms_;
    build_reported_ = true;
  }
  update_locals(in, f);  // first: rebuilding a map runs this contribution's kernels on its texels
  std::vector<glm::vec4> rgb = shade(in, f);
  if (!locals_.empty()) {
    // the object's pixels read the local map: no far-map visibility (the map holds the scene's
    // occluders) and no background (the far pass draws it)
    FrameSettings ls = in.settings;
    ls.declared.env_visibility = scene::choice_name(scene::EnvVisibilityKind::none);
    ls.declared.env_background = scene::choice_name(scene::EnvBackground::hide);
    for (auto& l : locals_) {
      if (!l->any) continue;
      const FrameInputs local{.rt = in.rt,
                              .surfaces = l->masked,
                              .count = in.count,
                              .settings = ls,
                              .frame = in.frame,
                              .lights = in.lights,
                              .camera = in.camera,
                              .geometry = in.geometry,
                              .view_version = in.view_version,
                              .host_lights = in.host_lights};
      ContributionFrame lf;
      l->env->prepare(local);
      const std::vector<glm::vec4> lrgb = l->env->shade(local, lf);
      f.step2_ms += lf.step2_ms;
      f.readback_ms += lf.readback_ms;
      for (std::size_t p = 0; p < rgb.size() && p < lrgb.size() && p < l->pixels.size(); ++p)
        if (l->pixels[p]) rgb[p] = lrgb[p];
    }
  }
  Timer readback;
  add_radiance(radiance, rgb);
  f.readback_ms += readback.ms();
  return f;
}

// Rebuilds the local maps whose key changed (LocalEnvironmentMap::key: luminaires, settings; not
// the camera) and finds each object's camera pixels when the surfaces changed.
void EnvironmentContribution::update_locals(const FrameInputs& in, ContributionFrame& f) {
  if (locals_.empty() || !in.geometry) return;
  if (!rays_ || rays_for_ != in.geometry) {
    rays_ = std::make_unique<ref::RayScene>(*in.geometry);
    rays_for_ = in.geometry;
  }
  std::vector<NfSurface> surfaces;
  for (auto& l : locals_) {
    const InputKey key = LocalEnvironmentMap::key(in);
    if (key != l->key || !l->env) {
      Timer total;
      FrameSettings ts = in.settings;  // the texels: no far-map visibility, no background
      ts.declared.env_visibility = scene::choice_name(scene::EnvVisibilityKind::none);
      ts.declared.env_background = scene::choice_name(scene::EnvBackground::hide);
      const LocalEnvironmentMap::FarShade far_shade = [&](const ::cl::Buffer& buf, int count, std::uint32_t frame) {
        const FrameInputs t{.rt = in.rt,
                            .surfaces = buf,
                            .count = count,
                            .settings = ts,
                            .frame = frame,
                            .lights = in.lights,
                            .geometry = in.geometry,
                            .host_lights = in.host_lights};
        ContributionFrame tf;
        return shade(t, tf);
      };
      LocalEnvironmentMap::Times times;
      ref::EnvironmentMap map = l->builder->build(in, *rays_, has_far_ ? &map_ : nullptr,
                                                  has_far_ ? far_shade : LocalEnvironmentMap::FarShade{}, times);
      l->env = std::make_unique<EnvironmentContribution>(rt_, std::move(map));
      l->env->set_kurt_table(kurt_table(materials_));
      l->env->set_filter(in.settings.declared.env_filter);
      l->env->set_param(in.settings.declared.env_param);
      l->env->build_reported_ = true;
      l->key = key;
      ++l->builds;
      l->times = times;
      f.step1_ms += total.ms();  // the frame that built it pays for it
    }
    // the last build's stages, every frame (render --stats shows the last frame's)
    const std::string& name = l->builder->spec().name;
    f.parts_ms.emplace_back(fmt::format("local '{}' rays", name), l->times.rays_ms);
    f.parts_ms.emplace_back(fmt::format("local '{}' visibility", name), l->times.visibility_ms);
    f.parts_ms.emplace_back(fmt::format("local '{}' shading", name), l->times.shading_ms);
    f.parts_ms.emplace_back(fmt::format("local '{}' pyramid", name), l->env->build_ms());
    if (in.view_version == 0 || in.view_version != l->pixels_version || in.count != l->pixels_count) {
      Timer timer;
      if (surfaces.size() != static_cast<std::size_t>(in.count)) {
        surfaces.resize(static_cast<std::size_t>(std::max(in.count, 0)));
        if (!surfaces.empty())
          cl::call(
              [&] {
                rt_.queue().enqueueReadBuffer(in.surfaces, CL_TRUE, 0, surfaces.size() * sizeof(NfSurface),
                                              surfaces.data());
              },
              "reading the surfaces for the local environment maps");
      }
      l->pixels = in.camera ? l->builder->owned_pixels(surfaces, *in.camera, *rays_)
                            : std::vector<std::uint8_t>(surfaces.size(), 0);
      l->any = std::any_of(l->pixels.begin(), l->pixels.end(), [](std::uint8_t b) { return b != 0; });
      if (l->any) {
        std::vector<NfSurface> masked = surfaces;
        for (std::size_t p = 0; p < masked.size(); ++p)
          if (!l->pixels[p]) masked[p].valid = 0;
        l->masked = upload_surfaces(rt_, masked);
      }
      l->pixels_version = in.view_version;
      l->pixels_count = in.count;
      l->pixels_ms = timer.ms();
      f.step1_ms += l->pixels_ms;
    }
    f.parts_ms.emplace_back(fmt::format("local '{}' pixels", l->builder->spec().name), l->pixels_ms);
  }
}

// One launch of env_shade over every surface; docs/environment.md has the estimators.
std::vector<glm::vec4> EnvironmentContribution::shade(const FrameInputs& in, ContributionFrame& f) {
  prepare(in);
  Timer wall;
  const EnvVisibility::Frame vis = vis_.run(in, map_, pyr_, lv_);  // dummies unless env_visibility sh
  f.step1_ms += vis.build_ms + vis.fit_ms;
  const std::size_t n = static_cast<std::size_t>(std::max(in.count, 1));
  if (out_bytes_ != n * sizeof(cl_float4)) {
    cl::call([&] { out_ = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float4)); },
             "environment output buffer");
    out_bytes_ = n * sizeof(cl_float4);
  }
  const auto& d = in.settings.declared;
  // camera: forward, right tan(fov_x / 2), up tan(fov_y / 2) (scene::Camera::ray); the fisheye:
  // forward with w = 1, unit right and up (the kernel maps the pixel as Camera::fisheye_ray does)
  cl_float4 cf{{0, 0, -1, 0}}, cr{{1, 0, 0, 0}}, cu{{0, 1, 0, 0}};
  cl_int2 wh{{1, 1}};
  if (in.camera) {
    const scene::Camera& c = *in.camera;
    const bool fisheye = c.projection == scene::Camera::Projection::fisheye;
    const double ty = fisheye ? 1.0 : c.tan_half_fov_y(), tx = fisheye ? 1.0 : ty * c.aspect();
    const glm::dvec3 fw = c.forward(), rt = c.right() * tx, up = c.true_up() * ty;
    cf = cl_float4{
        {static_cast<float>(fw.x), static_cast<float>(fw.y), static_cast<float>(fw.z), fisheye ? 1.0f : 0.0f}};
    cr = cl_float4{{static_cast<float>(rt.x), static_cast<float>(rt.y), static_cast<float>(rt.z), 0}};
    cu = cl_float4{{static_cast<float>(up.x), static_cast<float>(up.y), static_cast<float>(up.z), 0}};
    wh = cl_int2{{c.width, c.height}};
  }
  const bool par = param_ == EnvParam::paraboloid;
  // sh diffuse without SH visibility: the brightest blocks as lights, the SH without them
  const int shl = scene::choice_value<scene::EnvDiffuse>(d.env_diffuse) == scene::EnvDiffuse::sh &&
                          scene::choice_value<scene::EnvVisibilityKind>(d.env_visibility) != scene::EnvVisibilityKind::sh
                      ? std::min(d.env_sh_lights, static_cast<int>(sh_lights_.size()))
                      : 0;
  if (shl != shl_count_) {
    std::vector<cl_float4> sf, lf;
    for (const auto& s : residual_sh(sh_, sh_lights_, shl))
      sf.push_back(cl_float4{{static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z), 0}});
    for (int i = 0; i < shl; ++i) {
      const ShLight& l = sh_lights_[static_cast<std::size_t>(i)];
      lf.push_back(
          cl_float4{{static_cast<float>(l.dir.x), static_cast<float>(l.dir.y), static_cast<float>(l.dir.z), 0}});
      lf.push_back(
          cl_float4{{static_cast<float>(l.flux.x), static_cast<float>(l.flux.y), static_cast<float>(l.flux.z), 0}});
    }
    if (lf.empty()) lf.push_back(cl_float4{{0, 0, 0, 0}});
    shr_buf_ = cl::upload(rt_, sf, "uploading the environment SH without its lights");
    shl_buf_ = cl::upload(rt_, lf, "uploading the environment SH lights");
    shl_count_ = shl;
  }
  // regular's patterns; any valid buffer otherwise (the kernel reads them only with NF_ENV_GLOSSY 5)
  const bool regular = regular_bytes_ > 0;
  shade_.bind(in.surfaces, in.count, pyr_, lv_, levels(),
              cl_float2{{static_cast<float>(map_.rotation_cos()), static_cast<float>(map_.rotation_sin())}}, shr_buf_,
              rows_, cols_, puv_, d.env_samples, static_cast<float>(resolved_k(d.env_k, filter_)),
              static_cast<cl_uint>(in.frame), static_cast<cl_uint>(d.seed), cf, cr, cu, wh, out_, par ? ppyr_ : pyr_,
              par ? plv_ : lv_, par ? paraboloid_levels() : levels(), kurt_, kurt_count_, *vis.coeffs, *vis.lsh,
              regular ? rpat_ : pyr_, regular ? rlob_ : pyr_, static_cast<float>(d.env_regular_eps),
              static_cast<float>(d.env_k > 0.0 ? d.env_k : 1.0),  // regular: no per-filter K
              shl_buf_, shl_count_);
  const ::cl::Event ev = rt_.launch(shade_.get(), ::cl::NDRange(static_cast<std::size_t>(std::max(in.count, 1))));
  cl::call([&] { ev.wait(); }, "environment kernel");
  f.step2_ms += cl::Runtime::event_ms(ev);
  f.wall_ms += wall.ms();
  Timer readback;
  std::vector<glm::vec4> rgb = read_radiance(rt_, out_, in.count, "reading the environment radiance");
  f.samples += static_cast<std::uint64_t>(in.count) * static_cast<std::uint64_t>(d.env_samples);
  f.readback_ms += readback.ms();
  return rgb;
}

std::size_t EnvironmentContribution::device_bytes() const {
  std::size_t local = 0;
  for (const auto& l : locals_)
    if (l->env) local += l->env->device_bytes() + (l->any ? local_surface_bytes(l->pixels.size()) : 0);
  return pyr_bytes_ + ppyr_bytes_ + table_bytes_ + out_bytes_ + 2 * 9 * 16 + 32 * std::max(shl_count_, 1) +
         kurt_table_bytes(static_cast<std::size_t>(kurt_count_)) + vis_.device_bytes() + local + regular_bytes_;
}

}  // namespace nf::render
