// nearfield render SCENE -o OUT.exr [--png OUT.png] [--stats STATS.json] [overrides]
// Renders a scene headless (DESIGN.md §5, §7): linear radiance to OpenEXR with every setting in
// its metadata, optionally a tone-mapped PNG and a stats JSON (docs/rendering.md). Outputs are
// written to temporary files and moved into place together at the end, so a failure leaves no
// output behind and never a partial file; an output that would replace the scene or one of its
// input files is refused before any work.
#include <cctype>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/frame.h"
#include "render/settings.h"
#include "render/stats.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

struct RenderCmd {
  std::string scene, out, png, stats;
  int width = 0, height = 0, frames = 1;
  std::map<std::string, std::string> settings;  // declared setting name -> its --option text (scene/settings.h)
  std::map<std::string, CLI::Option*> given;    // option name -> its CLI11 option
  bool has(const std::string& name) const {
    auto it = given.find(name);
    return it != given.end() && it->second->count() > 0;
  }
};

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

void check_extension(const std::string& path, const std::string& ext, const std::string& option) {
  if (lower(fs::path(path).extension().string()) != ext)
    fail(fmt::format("{} {}: the file name must end in {}", option, path, ext));
}

fs::path canonical_or_self(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p).lexically_normal() : c;
}

// Files a JSON document names: every string value that names an existing regular file, resolved
// against `base`; .json and .gltf files found that way are followed (depth-limited), so a scene's
// luminaire manifests bring their EXR files and glTF files their buffers and images.
void collect_inputs(const fs::path& file, std::set<fs::path>& out, int depth) {
  out.insert(canonical_or_self(file));
  const std::string ext = lower(file.extension().string());
  if (depth <= 0 || (ext != ".json" && ext != ".gltf")) return;
  std::ifstream in(file);
  if (!in) return;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return;
  const fs::path base = file.parent_path();
  std::vector<const nlohmann::json*> stack{&j};
  while (!stack.empty()) {
    const nlohmann::json* v = stack.back();
    stack.pop_back();
    if (v->is_string()) {
      const std::string s = v->get<std::string>();
      if (s.empty() || s.size() > 4096 || s.rfind("data:", 0) == 0) continue;
      std::error_code ec;
      const fs::path p = fs::path(s).is_absolute() ? fs::path(s) : base / s;
      if (fs::is_regular_file(p, ec) && !out.count(canonical_or_self(p))) collect_inputs(p, out, depth - 1);
    } else if (v->is_structured()) {
      for (const auto& child : *v) stack.push_back(&child);
    }
  }
}

// Refuses outputs that coincide with each other or with an input.
void check_outputs(const RenderCmd& o, const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::set<fs::path> inputs;
  collect_inputs(o.scene, inputs, 3);
  std::set<fs::path> seen;
  for (const auto& [option, path] : outputs) {
    const fs::path c = canonical_or_self(path);
    if (!seen.insert(c).second) fail(fmt::format("{} {}: the same file is given for two outputs", option, path));
    std::error_code ec;
    bool clash = inputs.count(c) > 0;
    for (const auto& in : inputs) clash = clash || (fs::exists(c, ec) && fs::equivalent(c, in, ec));
    if (clash) fail(fmt::format("{} {}: refusing to overwrite an input of the scene {}", option, path, o.scene));
  }
}

// Command-line overrides of the scene's render settings and camera resolution.
void apply_overrides(const RenderCmd& o, scene::Scene& s) {
  for (const auto& decl : scene::settings_table())
    if (o.has(decl.cli_name())) scene::set_setting_text(s.render, decl, o.settings.at(decl.name), decl.cli_name());
  auto& c = s.camera;
  const double aspect = c.aspect();
  if (o.has("--width") && o.has("--height")) {
    c.width = o.width;
    c.height = o.height;
  } else if (o.has("--width")) {  // keep the scene's aspect ratio
    c.width = o.width;
    c.height = std::max(1, static_cast<int>(std::lround(o.width / aspect)));
  } else if (o.has("--height")) {
    c.height = o.height;
    c.width = std::max(1, static_cast<int>(std::lround(o.height * aspect)));
  }
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

void run_render(const RenderCmd& o) {
  Timer total;
  check_extension(o.out, ".exr", "-o");
  if (!o.png.empty()) check_extension(o.png, ".png", "--png");
  if (o.frames < 1) fail(fmt::format("--frames must be >= 1, got {}", o.frames));
  std::vector<std::pair<std::string, std::string>> outputs{{"-o", o.out}};
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.stats.empty()) outputs.emplace_back("--stats", o.stats);
  std::vector<std::pair<std::string, double>> phases;

  Timer t;
  scene::Scene scene = scene::load_scene(o.scene);
  check_outputs(o, outputs);
  apply_overrides(o, scene);
  render::frame_settings(scene.render);  // validate before any heavy work
  // Temporary outputs now: a missing output folder fails before rendering.
  AtomicFile exr_file(o.out);
  std::unique_ptr<AtomicFile> png_file, stats_file;
  if (!o.png.empty()) png_file = std::make_unique<AtomicFile>(o.png);
  if (!o.stats.empty()) stats_file = std::make_unique<AtomicFile>(o.stats);
  phases.emplace_back("load_scene", t.ms());

  t.reset();
  Progress progress("render", 1 + 3 * static_cast<std::size_t>(o.frames) + 1);
  render::RendererOptions ropt;
  ropt.cl_device = global_options().cl_device;
  ropt.on_stage = [&progress] { progress.advance(); };
  render::Renderer renderer(std::move(scene), ropt);
  progress.advance();
  phases.emplace_back("setup", t.ms());

  t.reset();
  for (int f = 0; f < o.frames; ++f) renderer.render_frame();
  renderer.tonemap_display();  // Step 3 in GL, as a display would do it (timed)
  phases.emplace_back("render", t.ms());

  t.reset();
  const Image hdr = renderer.accumulated();
  render::RenderStats stats = renderer.stats();
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", o.scene},
                        {"nearfield:content", "linear radiance, W m^-2 sr^-1 (the luminaires' units)"},
                        {"nearfield:cl_device", stats.cl_device},
                        {"nearfield:gl_renderer", stats.gl_renderer},
                        {"nearfield:frames", std::to_string(renderer.frames())},
                        {"nearfield:samples", std::to_string(stats.total.samples)},
                        {"nearfield:render_ms", fmt::format("{:.3f}", stats.total.wall_ms)},
                        {"nearfield:date", utc_now()}};
  for (const auto& kv : stats.settings) attrs.push_back(kv);
  write_exr(exr_file.temp_path(), hdr, attrs);
  if (png_file) write_png(png_file->temp_path(), renderer.tonemapped());
  progress.advance();
  progress.finish();
  phases.emplace_back("write", t.ms());
  phases.emplace_back("total", total.ms());
  if (stats_file) {
    const std::string text = render::to_json(stats, phases);
    std::ofstream out(stats_file->temp_path(), std::ios::binary);
    out << text;
    out.close();
    if (!out) fail(fmt::format("{}: write failed", o.stats));
  }
  exr_file.commit();
  if (png_file) png_file->commit();
  if (stats_file) stats_file->commit();

  std::string text = render::summary(stats);
  text += fmt::format("wrote {}", o.out);
  if (png_file) text += fmt::format(", {}", o.png);
  if (stats_file) text += fmt::format(", {}", o.stats);
  text += fmt::format(" ({:.0f} ms in all)\n", total.ms());
  if (log::level() != log::Level::quiet) std::fputs(text.c_str(), stdout);
}

const CommandRegistration reg("render", [](CLI::App& app) {
  static RenderCmd o;
  auto* cmd = app.add_subcommand("render", "Render a scene headless to OpenEXR (+ PNG, stats JSON)");
  cmd->add_option("scene", o.scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--out", o.out, "Output OpenEXR file (linear radiance)")->required();
  cmd->add_option("--png", o.png, "Also write a tone-mapped PNG");
  cmd->add_option("--stats", o.stats, "Also write per-step times, samples and memory as JSON");
  cmd->add_option("--frames", o.frames, "Progressive frames to accumulate (sequences advance per frame)")
      ->capture_default_str();
  auto add = [&](const std::string& name, auto& var, const std::string& help) {
    o.given[name] = cmd->add_option(name, var, help);
  };
  // one override per declared setting (scene/settings.cpp), validated like the scene file
  for (const auto& decl : scene::settings_table())
    add(decl.cli_name(), o.settings[decl.name], fmt::format("{} ({})", decl.doc, decl.range_text()));
  add("--width", o.width, "Image width (alone: keeps the scene's aspect ratio)");
  add("--height", o.height, "Image height (alone: keeps the scene's aspect ratio)");
  cmd->callback([] { run_render(o); });
});

}  // namespace
}  // namespace nf::app
