// The declarations of every render setting (docs/settings.md) and the functions that serve
// scene files, the command line, the viewer and metadata from them.
#include "scene/settings.h"

#include <fmt/format.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <type_traits>

#include "core/error.h"
#include "core/excerpt.h"
#include "scene/choices.h"
#include "scene/settings_check.h"

namespace nf::scene {
namespace {

using json = nlohmann::json;
using Check = std::function<void(double, const JsonWhere&)>;

// Binds a setting to a field through `ref`, a generic lambda returning a reference to the field
// of a (const or not) RenderSettings. A choice's values are the names of its enum E (scene/choices.h).
template <typename E, typename Ref>
Setting choice(std::string name, std::string path, std::string contribution, SettingEffect effect, std::string doc,
               Ref ref) {
  Setting s;
  s.name = std::move(name);
  s.json_path = std::move(path);
  s.type = SettingType::choice;
  s.choices = choice_names<E>();
  s.contribution = std::move(contribution);
  s.effect = effect;
  s.doc = std::move(doc);
  s.get = [ref](const RenderSettings& r) { return std::string(ref(r)); };
  s.set = [ref, c = s.choices](RenderSettings& r, const json& v, const JsonWhere& w) { ref(r) = json_choice(v, w, c); };
  return s;
}

template <typename Ref>
Setting integer(std::string name, std::string path, long long lo, long long hi, std::string contribution,
                SettingEffect effect, std::string doc, Ref ref, Check check = {}) {
  Setting s;
  s.name = std::move(name);
  s.json_path = std::move(path);
  s.type = SettingType::integer;
  s.lo = static_cast<double>(lo);
  s.hi = static_cast<double>(hi);
  s.contribution = std::move(contribution);
  s.effect = effect;
  s.doc = std::move(doc);
  s.get = [ref](const RenderSettings& r) { return std::to_string(ref(r)); };
  s.set = [ref, lo, hi, check](RenderSettings& r, const json& v, const JsonWhere& w) {
    const int i = json_integer(v, w, lo, hi);
    if (check) check(i, w);
    using T = std::remove_reference_t<decltype(ref(r))>;
    ref(r) = static_cast<T>(i);
  };
  return s;
}

// A real in (lo, hi]: lo itself is refused with "must be > lo".
template <typename Ref>
Setting positive_real(std::string name, std::string path, double hi, std::string contribution, SettingEffect effect,
                      std::string doc, Ref ref) {
  Setting s;
  s.name = std::move(name);
  s.json_path = std::move(path);
  s.type = SettingType::real;
  s.lo = 0.0;
  s.hi = hi;
  s.contribution = std::move(contribution);
  s.effect = effect;
  s.doc = std::move(doc);
  s.get = [ref](const RenderSettings& r) { return fmt::format("{}", ref(r)); };
  s.set = [ref, hi](RenderSettings& r, const json& v, const JsonWhere& w) {
    const double d = json_number(v, w, 0.0, hi);
    if (d <= 0.0) w.fail("must be > 0");
    ref(r) = d;
  };
  return s;
}

// A real in [0, hi] (0 has a meaning of its own, stated in the doc).
template <typename Ref>
Setting nonnegative_real(std::string name, std::string path, double hi, std::string contribution, SettingEffect effect,
                         std::string doc, Ref ref) {
  Setting s = positive_real(std::move(name), std::move(path), hi, std::move(contribution), effect, std::move(doc), ref);
  s.lo_open = false;
  s.set = [ref, hi](RenderSettings& r, const json& v, const JsonWhere& w) { ref(r) = json_number(v, w, 0.0, hi); };
  return s;
}

// A real in [lo, hi].
template <typename Ref>
Setting closed_real(std::string name, std::string path, double lo, double hi, std::string contribution,
                    SettingEffect effect, std::string doc, Ref ref) {
  Setting s = positive_real(std::move(name), std::move(path), hi, std::move(contribution), effect, std::move(doc), ref);
  s.lo = lo;
  s.lo_open = false;
  s.set = [ref, lo, hi](RenderSettings& r, const json& v, const JsonWhere& w) { ref(r) = json_number(v, w, lo, hi); };
  return s;
}

// The setting applies only with shadow maps.
Setting with_shadow_maps(Setting s) {
  s.applies = [](const RenderSettings& r) {
    return choice_value<Visibility>(r.visibility, "visibility") == Visibility::shadowmaps;
  };
  s.applies_doc = "with shadow maps";
  return s;
}

std::vector<Setting> declare() {
  constexpr auto R = SettingEffect::restart;
  constexpr auto S0 = SettingEffect::step0;
  constexpr auto D = SettingEffect::display;
  constexpr long long kMaxSpp = 1 << 24;
  return {
      choice<Method>(
          "method", "method", "luminaires", R, "how samples are drawn on the light-field images (docs/sampling.md)",
          [](auto& r) -> auto& { return r.method; }),
      choice<SamplerKind>(
          "sampler", "sampler", "luminaires", R, "where the 2D sample points come from",
          [](auto& r) -> auto& { return r.sampler; }),
      integer(
          "spp", "spp", 1, kMaxSpp, "luminaires", R, "K: samples per pixel per frame (Eq. 12)",
          [](auto& r) -> auto& { return r.spp; }),
      integer(
          "kmax", "kmax", 0, kMaxSpp, "luminaires", R, "K_max: cap of samples per image and pixel (0 = none)",
          [](auto& r) -> auto& { return r.kmax; }),
      integer(
          "search_depth", "search_depth", -1, 1024, "luminaires", R,
          "CDF evaluations per 1D inversion (-1 = unlimited, exact)", [](auto& r) -> auto& { return r.search_depth; },
          [](double v, const JsonWhere& w) {
            if (v == 0.0) w.fail("must be -1 (unlimited) or 1..1024");
          }),
      choice<SearchKind>(
          "search", "search", "luminaires", R, "CDF inversion: modified secant or bisection",
          [](auto& r) -> auto& { return r.search; }),
      choice<Balance>(
          "balance", "balance", "luminaires", R, "rounding of K_m(p) = K A_m / A (min1 and roulette are unbiased)",
          [](auto& r) -> auto& { return r.balance; }),
      choice<BalanceEstimate>(
          "balance_estimate", "balance_estimate", "luminaires", R,
          "what K_m(p) is balanced from: a 4-read block estimate of A_m(p), refined to the exact A_m(p) for the "
          "images that get samples for sure (blocks; the fused structure), or the exact A_m(p) of every image "
          "(exact); both unbiased "
          "(docs/sampling.md \"Balancing from block estimates\")",
          [](auto& r) -> auto& { return r.balance_estimate; }),
      choice<Structure>(
          "structure", "structure", "luminaires", R, "per-image Step 1/2 passes (paper) or one fused pass",
          [](auto& r) -> auto& { return r.structure; }),
      choice<Mis>(
          "mis", "mis", "luminaires", R,
          "multiple importance sampling of the light-field samples with BRDF samples on glossy surfaces "
          "(ggx, kurt: up to K more directions per pixel, fewer for rough GGX): none, balance or power heuristic "
          "(docs/mis.md); nearfield reference (--mis): its own MIS, one BRDF sample per surface point "
          "(docs/reference.md)",
          [](auto& r) -> auto& { return r.mis; }),
      choice<Visibility>(
          "visibility", "visibility", "frame", S0,
          "luminaire visibility: none or shadow maps at the reference light positions",
          [](auto& r) -> auto& { return r.visibility; }),
      with_shadow_maps(integer(
          "shadow_map_size", "shadow_map_size", 16, 4096, "frame", S0, "pixels per side of each shadow map",
          [](auto& r) -> auto& { return r.shadow_map_size; })),
      with_shadow_maps(nonnegative_real(
          "shadow_far_distance", "shadow_far_distance", 1e6, "frame", S0,
          "metres: luminaire instances farther from the camera get one shadow map for all cells instead of one "
          "per cell (an approximation: hard shadows from the lens centre; docs/rendering.md); 0 = every instance "
          "exact",
          [](auto& r) -> auto& { return r.shadow_far_distance; })),
      with_shadow_maps(choice<VisibilityPass>(
          "visibility_pass", "visibility_pass", "frame", S0,
          "where the shadow maps are tested per pixel: an OpenCL kernel or the GL compute pass (same test)",
          [](auto& r) -> auto& { return r.visibility_pass; })),
      integer(
          "seed", "seed", 0, 2147483647, "luminaires", R, "seed of the random and scrambled sequences",
          [](auto& r) -> auto& { return r.seed; }),
      integer(
          "lanes", "lanes", 0, 16, "luminaires", R, "surfaces per OpenCL work-item: 1, 4, 8, 16 (0 = automatic)",
          [](auto& r) -> auto& { return r.lanes; },
          [](double v, const JsonWhere& w) {
            if (v != 0 && v != 1 && v != 4 && v != 8 && v != 16)
              w.fail(fmt::format("must be 0 (automatic), 1, 4, 8 or 16, got {}", v));
          }),
      integer(
          "roulette_block", "roulette_block", 1, 1024, "luminaires", R,
          "consecutive surfaces that share the roulette's random decision per image and frame "
          "(1 = per pixel; larger: SIMD lanes skip the same images, neighbours' noise correlated)",
          [](auto& r) -> auto& { return r.roulette_block; }),
      integer(
          "surface_shuffle", "surface_shuffle", 0, 20, "luminaires", R,
          "log2 of the chunks (image tiles, 8 x 8 at 6) inside which the kernels visit surfaces in a fixed "
          "pseudo-random order, so roulette blocks and SIMD lanes are scattered instead of runs along a row "
          "(0 = row order; docs/sampling.md \"Surface order\")",
          [](auto& r) -> auto& { return r.surface_shuffle; }),
      integer(
          "pixel_cache", "pixel_cache", 0, 1048576, "luminaires", R,
          "MiB of device memory for A_m(p) kept across progressive frames (0 = recompute every frame)",
          [](auto& r) -> auto& { return r.pixel_cache; }),
      choice<LightSelection>(
          "light_selection", "light_selection", "luminaires", R,
          "several lights: all = every luminaire instance at every pixel with K samples each, every far-field "
          "light in full; flat = K is the pixel's budget, selection_picks picks per pixel and frame among the "
          "instances and far-field lights drawn with probabilities q_i(p) from a flat CDF, weighted 1/(M q_i); "
          "auto = flat from 26 light-field instances on, all below (docs/sampling.md \"Light selection\")",
          [](auto& r) -> auto& { return r.light_selection; }),
      integer(
          "selection_picks", "selection_picks", 1, 15, "luminaires", R,
          "M, picks per pixel and frame with light selection (systematic sampling of q_i; a light picked c "
          "times gets round(c K / M) samples, weight c / (M q_i); docs/sampling.md \"Light selection\")",
          [](auto& r) -> auto& { return r.selection_picks; }),
      choice<SelectionEstimate>(
          "selection_estimate", "selection_estimate", "luminaires", R,
          "the estimate f_i(p) light selection draws from: table = the direction table's intensity estimate "
          "(measured better at 32 and 128 instances), bound = a conservative bound of the instance's "
          "contribution E_i(p) (docs/sampling.md \"The bound\")",
          [](auto& r) -> auto& { return r.selection_estimate; }),
      choice<EnvGlossy>(
          "env_glossy", "env_glossy", "environment", R,
          "environment glossy estimator: BRDF sampling, filtered importance sampling, rotated, map sampling, "
          "filtered map sampling, Luksch 2014 regular pattern (docs/regular-sampling.md)",
          [](auto& r) -> auto& { return r.env_glossy; }),
      integer(
          "env_samples", "env_samples", 1, 4096, "environment", R,
          "N: environment directions per pixel per frame (glossy, and diffuse with env_diffuse mc)",
          [](auto& r) -> auto& { return r.env_samples; }),
      closed_real(
          "env_regular_eps", "env_regular_eps", 1e-6, 0.5, "environment", R,
          "eps0 of env_glossy regular: the pattern spans the lobe down to D = eps0 D(peak) (Luksch Eq. 11); "
          "the range where constant-sky results stay within 15 % of the closed form (docs/regular-sampling.md)",
          [](auto& r) -> auto& { return r.env_regular_eps; }),
      nonnegative_real(
          "env_k", "env_k", 1e6, "environment", R,
          "K: level bias of the filtered lookup, l = log4(K W H / (N p J)); 0 = per filter (box 4, gauss 1); "
          "regular: factor on its samples' solid angle (0 = 1)",
          [](auto& r) -> auto& { return r.env_k; }),
      choice<EnvKernel>(
          "env_kernel", "env_kernel", "environment", R,
          "env-fis kernel size: point density (Tokuyoshi Eq. 1) or integrated density by bisection (Eq. 3)",
          [](auto& r) -> auto& { return r.env_kernel; }),
      choice<EnvFilter>(
          "env_filter", "env_filter", "environment", R,
          "filter of the environment pyramid: 2x2 box, 4x4 (1 3 3 1)/8 or 6x6 (1 5 10 10 5 1)/32 binomial",
          [](auto& r) -> auto& { return r.env_filter; }),
      choice<EnvParam>(
          "env_param", "env_param", "environment", R,
          "parametrisation of the filtered pyramid: the map's lat-long grid or a dual paraboloid about +-y",
          [](auto& r) -> auto& { return r.env_param; }),
      choice<EnvDiffuse>(
          "env_diffuse", "env_diffuse", "environment", R,
          "environment diffuse term: order-2 SH irradiance or cosine-sampled Monte Carlo",
          [](auto& r) -> auto& { return r.env_diffuse; }),
      integer(
          "env_sh_lights", "env_sh_lights", 0, 256, "environment", R,
          "env_diffuse sh: the map's brightest blocks (at most 2.8 degrees) taken out of the order-2 SH and shaded "
          "as directional lights; 0 = the SH alone (docs/environment.md)",
          [](auto& r) -> auto& { return r.env_sh_lights; }),
      choice<EnvBackground>(
          "env_background", "env_background", "environment", R,
          "camera rays that miss the geometry see the environment (show) or black (hide)",
          [](auto& r) -> auto& { return r.env_background; }),
      choice<EnvVisibilityKind>(
          "env_visibility", "env_visibility", "environment", R,
          "environment visibility: none or order-4 SH of V cos fitted to N_v shadow maps",
          [](auto& r) -> auto& { return r.env_visibility; }),
      integer(
          "env_visibility_samples", "env_visibility_samples", 1, 256, "environment", R,
          "N_v: shadow-map directions (env-map importance sampled) of the SH visibility",
          [](auto& r) -> auto& { return r.env_visibility_samples; }),
      choice<Indirect>(
          "indirect", "indirect", "indirect", R,
          "one-bounce indirect light from the luminaires: none or VSGLs (Tokuyoshi 2016)",
          [](auto& r) -> auto& { return r.indirect; }),
      integer(
          "rsm_size", "rsm_size", 16, 4096, "indirect", R, "texels per side of each luminaire's RSM (a power of two)",
          [](auto& r) -> auto& { return r.rsm_size; },
          [](double v, const JsonWhere& w) {
            const auto i = static_cast<long long>(v);
            if ((i & (i - 1)) != 0) w.fail(fmt::format("must be a power of two, got {}", v));
          }),
      integer(
          "vsgl_count", "vsgl_count", 64, 4096, "indirect", R, "N_v: VSGLs per luminaire instance",
          [](auto& r) -> auto& { return r.vsgl_count; }),
      choice<VsglKernel>(
          "vsgl_kernel", "vsgl_kernel", "indirect", R,
          "VSGL kernel size: point density (Eq. 1, totals Eq. 4) or PDF integral (Eq. 3, totals Eq. 5)",
          [](auto& r) -> auto& { return r.vsgl_kernel; }),
      positive_real(
          "vsgl_k", "vsgl_k", 1e6, "indirect", R, "K: PDF mass K/N_v per integral kernel (Eq. 3)",
          [](auto& r) -> auto& { return r.vsgl_k; }),
      choice<VsglPoints>(
          "vsgl_points", "vsgl_points", "indirect", R, "stratified point set warped to the VSGL centres",
          [](auto& r) -> auto& { return r.vsgl_points; }),
      integer(
          "vsgl_shadowed", "vsgl_shadowed", 0, 4096, "indirect", R,
          "per instance, the k strongest VSGLs get cube shadow maps (0: unshadowed; maps capped at 1 GiB)",
          [](auto& r) -> auto& { return r.vsgl_shadowed; }),
      choice<VsglSplit>(
          "vsgl_split", "vsgl_split", "indirect", R,
          "VSGL clusters split by normal: none, or one pyramid per dominant signed axis of the VPL normals",
          [](auto& r) -> auto& { return r.vsgl_split; }),
      positive_real(
          "exposure", "tonemap/exposure", 1e300, "display", D, "tone mapping exposure (> 0)",
          [](auto& r) -> auto& { return r.tonemap.exposure; }),
      positive_real(
          "gamma", "tonemap/gamma", 100.0, "display", D, "tone mapping gamma (> 0)",
          [](auto& r) -> auto& { return r.tonemap.gamma; }),
  };
}

std::string pointer_join(const std::string& base, const std::string& path) { return base + "/" + path; }

json parse_text(const Setting& s, const std::string& text, const JsonWhere& w) {
  if (s.type == SettingType::choice) {  // typed names may use '_' for '-' ("halton_scrambled")
    std::string dashed = text;
    std::replace(dashed.begin(), dashed.end(), '_', '-');
    const bool known = std::find(s.choices.begin(), s.choices.end(), text) != s.choices.end();
    return json(!known && std::find(s.choices.begin(), s.choices.end(), dashed) != s.choices.end() ? dashed : text);
  }
  errno = 0;
  char* end = nullptr;
  if (s.type == SettingType::integer) {
    const long long i = std::strtoll(text.c_str(), &end, 10);
    if (!text.empty() && end == text.c_str() + text.size() && errno == 0) return json(i);
  }
  errno = 0;
  const double d = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) w.fail(fmt::format("'{}' is not a number", excerpt(text)));
  if (errno == ERANGE && std::fabs(d) > 1.0) w.fail(fmt::format("'{}' is out of the range of a double", excerpt(text)));
  return json(d);  // subnormals parse with ERANGE and are kept
}

}  // namespace

std::string to_string(SettingEffect e) {
  switch (e) {
    case SettingEffect::display:
      return "display";
    case SettingEffect::restart:
      return "restart";
    case SettingEffect::step0:
      return "step0";
  }
  return "?";
}

std::string Setting::cli_name() const {
  std::string n = name;
  std::replace(n.begin(), n.end(), '_', '-');
  return "--" + n;
}

std::string Setting::range_text() const {
  if (type == SettingType::choice) return join_names(choices);
  if (type == SettingType::integer)
    return fmt::format("{}..{}", static_cast<long long>(lo), static_cast<long long>(hi));
  return fmt::format("{} {}, <= {}", lo_open ? ">" : ">=", lo, hi);
}

const std::vector<Setting>& settings_table() {
  static const std::vector<Setting> table = declare();
  return table;
}

const Setting* find_setting(const std::string& name) {
  std::string n = name;
  if (n.rfind("--", 0) == 0) n = n.substr(2);
  std::replace(n.begin(), n.end(), '-', '_');
  for (const auto& s : settings_table())
    if (s.name == n) return &s;
  return nullptr;
}

std::string setting_names_text() {
  std::vector<std::string> names;
  for (const auto& s : settings_table()) names.push_back(s.name);
  return join_names(names);
}

void set_setting_text(RenderSettings& r, const Setting& s, const std::string& text, const std::string& where) {
  const JsonWhere w{"", where};
  s.set(r, parse_text(s, text, w), w);
}

void check_setting(const RenderSettings& r, const std::string& name, const std::string& where) {
  const Setting* s = find_setting(name);
  if (s == nullptr) fail(fmt::format("check_setting: no setting '{}'", name));
  RenderSettings copy = r;  // the value is written back unchanged when it passes
  set_setting_text(copy, *s, s->get(r), where + "." + s->name);
}

RenderSettings parse_render_settings(const json& v, const JsonWhere& where) {
  // keys of the "render" object: each setting's first path component
  std::vector<std::string> keys;
  for (const auto& s : settings_table()) {
    const std::string k = s.json_path.substr(0, s.json_path.find('/'));
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  auto check_object = [&](const json& o, const std::string& ptr, const std::vector<std::string>& allowed) {
    if (!o.is_object()) JsonWhere{where.file, ptr}.fail(fmt::format("expected an object, got {}", json_type_name(o)));
    for (auto it = o.begin(); it != o.end(); ++it)
      if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
        JsonWhere{where.file, pointer_join(ptr, it.key())}.fail(
            fmt::format("unknown key '{}' (allowed here: {})", excerpt(it.key()), join_names(allowed)));
  };
  check_object(v, where.ptr, keys);
  RenderSettings r;
  for (const auto& s : settings_table()) {
    const json* node = &v;
    std::string ptr = where.ptr;
    std::size_t from = 0;
    bool present = true;
    while (present) {
      const std::size_t slash = s.json_path.find('/', from);
      const std::string key = s.json_path.substr(from, slash - from);
      if (!node->contains(key)) {
        present = false;
        break;
      }
      node = &(*node)[key];
      ptr = pointer_join(ptr, key);
      if (slash == std::string::npos) break;
      // an intermediate object ("tonemap"): its keys are the settings below it
      std::vector<std::string> below;
      const std::string prefix = s.json_path.substr(0, slash + 1);
      for (const auto& t : settings_table())
        if (t.json_path.rfind(prefix, 0) == 0) below.push_back(t.json_path.substr(prefix.size()));
      check_object(*node, ptr, below);
      from = slash + 1;
    }
    if (present) s.set(r, *node, JsonWhere{where.file, ptr});
  }
  return r;
}

std::vector<std::pair<std::string, std::string>> settings_attributes(const RenderSettings& r) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& s : settings_table()) out.emplace_back("nearfield:" + s.name, s.get(r));
  return out;
}

SettingEffect change_effect(const RenderSettings& a, const RenderSettings& b) {
  SettingEffect e = SettingEffect::display;
  for (const auto& s : settings_table())
    if (s.get(a) != s.get(b) && (!s.applies || s.applies(a) || s.applies(b))) e = std::max(e, s.effect);
  return e;
}

std::vector<std::string> settings_key(const RenderSettings& r, const std::vector<std::string>& keys) {
  for (const auto& k : keys) {
    const auto& t = settings_table();
    if (std::none_of(t.begin(), t.end(), [&](const Setting& s) { return s.contribution == k || s.name == k; }))
      fail(fmt::format("settings_key: '{}' is neither a setting nor a group", k));
  }
  std::vector<std::string> out;
  for (const auto& s : settings_table())
    if (std::find(keys.begin(), keys.end(), s.contribution) != keys.end() ||
        std::find(keys.begin(), keys.end(), s.name) != keys.end())
      out.push_back(s.get(r));
  return out;
}

bool same_settings(const RenderSettings& a, const RenderSettings& b) {
  for (const auto& s : settings_table())
    if (s.get(a) != s.get(b)) return false;
  return true;
}

}  // namespace nf::scene
