// nearfield glare IMAGE.hdr|.exr [--json] [--road [--lav L]] [--threshold L | --factor F] [--merge RAD]
// Discomfort glare (UGR, CIE 117-1995) and, for roads, disability glare (veiling luminance and TI,
// CIE 140 / EN 13201-3) from a luminance image with its view (docs/glare.md).
#include <cstdio>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "app/command.h"
#include "app/glare.h"
#include "core/error.h"

namespace nf::app {
namespace {

struct GlareCmd {
  std::string image;
  bool json = false;
  GlareOptions options;
  double lav = 0.0;
  CLI::Option* lav_opt = nullptr;
  CLI::Option* threshold_opt = nullptr;
};

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
  const LuminanceImage im = load_luminance_image(o.image);
  const GlareResult r = evaluate_glare(im, o.options);
  const std::string out = o.json ? glare_json(o.image, im, o.options, r) : text_report(r, o.options);
  std::fputs(out.c_str(), stdout);
}

const CommandRegistration reg("glare", [](CLI::App& app) {
  static GlareCmd o;
  auto* cmd = app.add_subcommand("glare", "UGR (CIE 117) and road TI (CIE 140) from a luminance image with its view");
  cmd->add_option("image", o.image, "Radiance picture (.hdr, with VIEW=) or nearfield OpenEXR (.exr)")->required();
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
