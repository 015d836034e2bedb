// nearfield glare IMAGE.hdr|.exr [--json] [--road [--lav L]] [--threshold L | --factor F] [--merge RAD]
// nearfield glare SCENE.json --eye X,Y,Z --look X,Y,Z [--up X,Y,Z] [--lb L] [--farfield] [--road --lav L]
// Discomfort glare (UGR, CIE 117-1995) and, for roads, disability glare (veiling luminance and TI,
// CIE 140 / EN 13201-3) from a luminance image with its view, or straight from a scene's
// luminaires seen from an eye point (docs/glare.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "app/command.h"
#include "app/glare.h"
#include "app/glare_direct.h"
#include "core/error.h"
#include "reference/ray_scene.h"
#include "render/luminaire_cache.h"
#include "scene/scene.h"

namespace nf::app {
namespace {

struct GlareCmd {
  std::string image;
  bool json = false;
  GlareOptions options;
  double lav = 0.0;
  CLI::Option* lav_opt = nullptr;
  CLI::Option* threshold_opt = nullptr;
  // direct mode (a scene)
  std::string eye, look, up;
  double lb = 0.0;
  CLI::Option* lb_opt = nullptr;
  bool farfield = false;
  int subdivide = 3;
  CLI::Option* subdivide_opt = nullptr;
};

// "X,Y,Z" (three finite numbers) for `option`.
glm::dvec3 parse_point(const std::string& text, const std::string& option) {
  glm::dvec3 v(0.0);
  std::size_t pos = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = text.find(',', pos);
    const std::string part = text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(x) || (k < 2) != (end != std::string::npos))
      fail(fmt::format("{}: expected X,Y,Z (three numbers), got '{}'", option, text));
    v[k] = x;
    pos = end + 1;
  }
  return v;
}

void run_direct(GlareCmd& o) {
  if (o.eye.empty() || o.look.empty())
    fail(fmt::format("glare {}: a scene needs the eye point and the line of sight: --eye X,Y,Z --look X,Y,Z", o.image));
  if (o.options.factor > 0.0) fail("--factor: the direct mode has no image mean; use --threshold");
  DirectOptions d;
  d.eye = parse_point(o.eye, "--eye");
  d.look = parse_point(o.look, "--look");
  if (!o.up.empty()) d.up = parse_point(o.up, "--up");
  d.threshold = o.options.threshold;
  d.road = o.options.road;
  d.lav = o.options.lav;
  d.farfield = o.farfield;
  if (o.subdivide_opt->count() > 0 && !(o.subdivide >= 1 && o.subdivide <= 64))
    fail(fmt::format("--subdivide must be in 1..64, got {}", o.subdivide));
  d.subdivide = o.subdivide;
  if (o.lb_opt->count() > 0) {
    if (!(o.lb > 0.0)) fail(fmt::format("--lb must be > 0 cd/m2, got {}", o.lb));
    d.lb = o.lb;
  }
  if (d.road && !d.lav) fail("--road: the direct mode has no image of the road; give its average luminance with --lav");
  const scene::Scene scene = scene::load_scene(o.image);
  if (scene.luminaires.empty() && scene.farfield_lights.empty())
    fail(fmt::format("{}: the scene has no luminaires (/luminaires, /farfield_lights): no glare to evaluate", o.image));
  const render::LuminaireSet set = render::load_luminaires(scene.luminaires, o.image);
  const ref::RayScene rays(scene.geometry);
  const DirectResult r = evaluate_direct(scene, set, rays, d);
  const std::string out = o.json ? direct_json(o.image, r, d) : direct_text(r, d);
  std::fputs(out.c_str(), stdout);
}

std::string text_report(const GlareResult& r, const GlareOptions& o) {
  std::string t = fmt::format("UGR {:.2f}\n", r.ugr);
  t += fmt::format("sources {} (threshold {:.6g} cd/m2), background luminance {:.6g} cd/m2 (E_ind {:.6g} lx)\n",
                   r.sources.size(), r.threshold, r.background_luminance, r.indirect_illuminance);
  for (std::size_t i = 0; i < r.sources.size(); ++i) {
    const auto& s = r.sources[i];
    t += fmt::format(
        "  source {}: L {:.6g} cd/m2, omega {:.6g} sr, {:.3f} deg off the line of sight (tau {:.1f}), "
        "p {:.4g}, E {:.6g} lx\n",
        i + 1, s.luminance, s.solid_angle, s.sigma_deg, s.tau_deg, s.position_index, s.eye_illuminance);
  }
  if (r.coverage < 0.99)
    t += fmt::format(
        "note: the image covers {:.1f} % of the front hemisphere's projected solid angle: E_ind and "
        "L_b count only what it shows (use a 180-degree fisheye)\n",
        100.0 * r.coverage);
  if (o.road) {
    t += fmt::format("Lv {:.6g} cd/m2\n", r.veiling_luminance);
    t += fmt::format("Lav {:.6g} cd/m2 ({})\n", r.lav, r.lav_source);
    t += fmt::format("TI {:.2f} %\n", r.ti);
  }
  return t;
}

void run_glare(GlareCmd& o) {
  if (o.options.factor > 0.0 && o.threshold_opt->count() > 0) fail("glare: give --threshold or --factor, not both");
  if (o.options.factor < 0.0) fail(fmt::format("--factor must be > 0, got {}", o.options.factor));
  if (!(o.options.threshold > 0.0)) fail(fmt::format("--threshold must be > 0 cd/m2, got {}", o.options.threshold));
  if (!(o.options.merge_angle >= 0.0 && o.options.merge_angle <= 3.15))
    fail(fmt::format("--merge must be in [0, pi] radians, got {}", o.options.merge_angle));
  if (o.lav_opt->count() > 0) {
    if (!o.options.road) fail("--lav needs --road");
    if (!(o.lav > 0.0)) fail(fmt::format("--lav must be > 0 cd/m2, got {}", o.lav));
    o.options.lav = o.lav;
  }
  const std::string ext = std::filesystem::path(o.image).extension().string();
  if (ext == ".json") {
    run_direct(o);
    return;
  }
  if (!o.eye.empty() || !o.look.empty() || !o.up.empty() || o.lb_opt->count() > 0 || o.farfield ||
      o.subdivide_opt->count() > 0)
    fail(
        fmt::format("glare {}: --eye/--look/--up/--lb/--farfield/--subdivide are for a scene (.json); an image "
                    "brings its own view",
                    o.image));
  const LuminanceImage im = load_luminance_image(o.image);
  const GlareResult r = evaluate_glare(im, o.options);
  const std::string out = o.json ? glare_json(o.image, im, o.options, r) : text_report(r, o.options);
  std::fputs(out.c_str(), stdout);
}

const CommandRegistration reg("glare", [](CLI::App& app) {
  static GlareCmd o;
  auto* cmd = app.add_subcommand(
      "glare", "UGR (CIE 117) and road TI (CIE 140) from a luminance image with its view, or from a scene and an eye");
  cmd->add_option("image", o.image,
                  "Radiance picture (.hdr, with VIEW=), nearfield OpenEXR (.exr), or a scene (.json: direct mode)")
      ->required();
  cmd->add_option("--eye", o.eye, "Direct mode: the eye point X,Y,Z (world, metres)");
  cmd->add_option("--look", o.look, "Direct mode: a point X,Y,Z on the line of sight");
  cmd->add_option("--up", o.up, "Direct mode: the up direction X,Y,Z (default 0,1,0)");
  o.lb_opt = cmd->add_option("--lb", o.lb, "Direct mode: the background luminance for UGR, cd/m2");
  cmd->add_flag("--farfield", o.farfield,
                "Direct mode: light-field luminaires by their own far field through their emitting area");
  o.subdivide_opt =
      cmd->add_option("--subdivide", o.subdivide, "Direct mode: midpoint samples per light-field pixel and axis")
          ->capture_default_str();
  cmd->add_flag("--json", o.json, "Print the result as JSON (sources with luminance, solid angle, direction)");
  cmd->add_flag("--road", o.options.road, "Also the veiling luminance and threshold increment TI (CIE 140)");
  o.lav_opt = cmd->add_option("--lav", o.lav, "Average road luminance for TI, cd/m2 (default: the road region)");
  o.threshold_opt = cmd->add_option("--threshold", o.options.threshold, "Glare-source luminance threshold, cd/m2")
                        ->capture_default_str();
  cmd->add_option("--factor", o.options.factor,
                  "Instead: threshold = FACTOR x the mean luminance of the field (evalglare's default is 5)");
  cmd->add_option("--merge", o.options.merge_angle, "Merge sources whose centres are this close, radians")
      ->capture_default_str();
  cmd->callback([] { run_glare(o); });
});

}  // namespace
}  // namespace nf::app
