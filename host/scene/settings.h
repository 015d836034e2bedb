#pragma once
// The render settings, declared once (docs/settings.md). Each declaration in settings.cpp gives
// a setting's name, type, range, default, documentation, the contribution it belongs to and
// what a change of it invalidates; that one declaration serves the scene file's "render" block,
// the command-line overrides (`--name`), the viewer's panel and `set NAME VALUE` scripts,
// validation (the same messages everywhere) and the EXR/JSON metadata ("nearfield:name").
// Adding a setting is one field below and one declaration in settings.cpp.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tonemap.h"
#include "scene/json_read.h"

namespace nf::scene {

// Render settings as written in the file (strings for choices); the render layer interprets them.
struct RenderSettings {
  std::string method = "ours";               // ours | paper | uniform | uniform-equal | ours-equal | global
  std::string sampler = "halton-scrambled";  // halton | halton-scrambled | random
  int spp = 200;                             // K, samples per pixel per frame, >= 1
  int kmax = 0;                              // K_max, cap of samples per image per pixel; 0 = no cap
  int search_depth = -1;                     // CDF evaluations per 1D inversion, 1..1024; -1 = unlimited (exact)
  std::string search = "secant";             // secant | binary
  std::string balance = "roulette";          // paper | min1 | roulette (min1 and roulette are unbiased)
  std::string balance_estimate = "exact";    // blocks | exact: what K_m(p) is balanced from (docs/sampling.md)
  std::string structure = "fused";           // per-image | fused (Step 1/2 passes)
  std::string mis = "power";                 // none | balance | power: MIS with BRDF samples (docs/mis.md)
  std::string visibility = "shadowmaps";     // none | shadowmaps
  int shadow_map_size = 256;                 // pixels per side of each cell's shadow map, 16..4096
  double shadow_far_distance = 0.0;          // metres; farther instances: one map for all cells (0 = off)
  // opencl | gl: where Step 0's visibility bitmask is computed (the same test)
  std::string visibility_pass = "opencl";
  std::uint32_t seed = 1;   // sampler seed (random, halton-scrambled)
  int lanes = 0;            // surfaces per OpenCL work-item: 0 (automatic), 1, 4, 8, 16
  int roulette_block = 16;  // consecutive surfaces sharing the roulette's decisions, 1..1024 (1 = per pixel)
  int surface_shuffle = 6;  // log2 of the chunk inside which surfaces are visited in random order; 0 = row order
  int pixel_cache = 1024;   // MiB for A_m(p) kept across progressive frames; 0 = off
  std::string light_selection = "auto";  // auto | all | flat (M picks per pixel and frame, q_i(p))
  int selection_picks = 1;               // M, picks per pixel and frame of light_selection flat, 1..15
  TonemapParams tonemap;                 // exposure, gamma
  // table | bound: the estimate f_i(p) light selection draws from (docs/sampling.md "The bound")
  std::string selection_estimate = "table";
  // environment (docs/environment.md)
  std::string env_glossy = "fis";       // mc | fis | fis-rotated | env-is | env-fis | regular
  int env_samples = 32;                 // N, glossy (and diffuse mc) directions per pixel per frame
  double env_regular_eps = 0.1;         // eps0 of the regular pattern (Luksch 2014 Eq. 11), (0, 0.999]
  double env_k = 0.0;                   // K, the filtered lookup's level bias; 0 = per filter (box 4, else 1)
  std::string env_kernel = "point";     // point | integral (env-fis kernel size, Tokuyoshi 2016 Eq. 1 / 3)
  std::string env_filter = "box";       // box | gauss4 | gauss6 (pyramid filter)
  std::string env_param = "latlong";    // latlong | paraboloid (filtered pyramid's parametrisation)
  std::string env_diffuse = "sh";       // sh | mc
  int env_sh_lights = 64;               // brightest map blocks taken out of the SH as lights, 0..256
  std::string env_background = "show";  // show | hide
  std::string env_visibility = "none";  // none | sh (Krivanek and Colbert 2008 §5.2, docs/env_visibility.md)
  int env_visibility_samples = 16;      // N_v, shadow-map directions of the SH visibility, 1..256
  // one-bounce indirect light (docs/indirect.md)
  std::string indirect = "none";           // none | vsgl
  int rsm_size = 256;                      // RSM texels per side, a power of two 16..4096
  int vsgl_count = 256;                    // N_v, VSGLs per luminaire instance, 64..4096
  std::string vsgl_kernel = "integral";    // point (Eq. 1, 4) | integral (Eq. 3, 5)
  double vsgl_k = 1.0;                     // K of Eq. 3 (integral kernels)
  std::string vsgl_points = "hammersley";  // hammersley | fibonacci (stratified centres)
  int vsgl_shadowed = 0;                   // VSGLs with shadow maps per instance (the strongest; 0: none)
  std::string vsgl_split = "axis";         // none | axis (clusters split by the normal's dominant axis)
};

// What a change of a setting invalidates, in increasing order: `display` only re-tone-maps the
// accumulated image, `restart` restarts the accumulation, `step0` also reruns Step 0 (G-buffer,
// shadow maps).
enum class SettingEffect { display, restart, step0 };
std::string to_string(SettingEffect e);

enum class SettingType { choice, integer, real };

struct Setting {
  std::string name;       // scene key in "render" (path: json_path), CLI `--` + name with '_' -> '-'
  std::string json_path;  // pointer below /render: "spp", "tonemap/exposure"
  SettingType type = SettingType::integer;
  std::vector<std::string> choices;  // type choice
  double lo = 0.0, hi = 0.0;         // inclusive range (integer, real)
  bool lo_open = true;               // real: lo itself is refused (> lo) unless false (>= lo)
  std::string doc;                   // one line for --help, the viewer and docs/settings.md
  std::string contribution;          // "luminaires", "frame", "display"
  SettingEffect effect = SettingEffect::restart;
  // When a change of it counts (empty: always): change_effect() ignores a change unless
  // applies(before) or applies(after), e.g. the shadow-map size only with shadow maps.
  std::function<bool(const RenderSettings&)> applies;
  std::string applies_doc;  // when it applies, in words ("with shadow maps"; docs/settings.md)
  // Reads the value as text ("ours", "64", "0.35"): metadata, the viewer, describe().
  std::function<std::string(const RenderSettings&)> get;
  // Validates and stores a JSON value; errors name `where` (file or option, and pointer).
  std::function<void(RenderSettings&, const nlohmann::json&, const JsonWhere&)> set;

  std::string cli_name() const;    // "--search-depth"
  std::string range_text() const;  // "ours | paper | ...", "1..16777216"
};

// Every setting, in the order of docs/settings.md.
const std::vector<Setting>& settings_table();
// The setting called `name` (the name or the CLI spelling with '-'); nullptr if none.
const Setting* find_setting(const std::string& name);
// All names, comma-separated (messages).
std::string setting_names_text();

// Sets one setting from text (command line, viewer, scripts): numbers for numeric settings, the
// name for choices. Throws nf::Error "where: message" with the same message a scene file gets.
void set_setting_text(RenderSettings& r, const Setting& s, const std::string& text, const std::string& where);
// Reads the scene file's "render" object (unknown keys are errors listing the allowed ones).
RenderSettings parse_render_settings(const nlohmann::json& v, const JsonWhere& where);
// ("nearfield:<name>", value) for every setting: EXR metadata and stats JSON.
std::vector<std::pair<std::string, std::string>> settings_attributes(const RenderSettings& r);
// The strongest declared effect among the settings that differ between a and b and apply to
// either (display when nothing differs). The one answer to "does this change restart the
// accumulation (restart) or also Step 0 (step0)?" (docs/rendering.md, "Invalidation").
SettingEffect change_effect(const RenderSettings& a, const RenderSettings& b);
// The values of the settings a component depends on: every setting whose `contribution` group or
// name is in `keys` ("luminaires", "visibility"), in table order. Components keep the key their
// state was built from and rebuild when it differs (render/input_key.h). Unknown keys throw.
std::vector<std::string> settings_key(const RenderSettings& r, const std::vector<std::string>& keys);
bool same_settings(const RenderSettings& a, const RenderSettings& b);
// The table of every setting as Markdown (`nearfield settings`, docs/settings.md).
std::string settings_markdown();

}  // namespace nf::scene
