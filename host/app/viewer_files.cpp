// The viewer's files (part of the frame loop, viewer_loop.h): image (EXR + PNG), scene, window
// screenshot, statistics JSON (viewer_stats.h). Every file is
// written to a temporary name and renamed into place; an image's EXR and PNG are committed
// together. Inputs of the scene are never overwritten: the scene file being viewed only after
// the user confirms in the panel (scripts: refused), every other file the scene uses (textures,
// environment map, glTF, luminaire manifests and images, IES/LDT files) never.
#include <epoxy/gl.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/output_checks.h"
#include "app/viewer_loop.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "scene/scene_writer.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

fs::path with_extension(fs::path p, const std::string& ext, const std::string& what) {
  if (p.empty()) fail(fmt::format("{}: no file name given", what));
  std::error_code ec;
  if (fs::is_directory(p, ec)) fail(fmt::format("{} {}: is a directory, expected a file name", what, p.string()));
  if (p.extension().empty()) p += ext;
  if (lower_extension(p) != ext) fail(fmt::format("{} {}: the file name must end in {}", what, p.string(), ext));
  return p;
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

}  // namespace

void Viewer::refuse_inputs(const fs::path& p, bool confirmed, const std::string& what) const {
  if (same_file(p, original_.file)) {
    if (confirmed) return;
    fail(fmt::format("{}: refusing to overwrite the scene file being viewed", p.string()));
  }
  check_not_input(what, p.string(), scene_inputs_, "the scene " + original_.file.string());
}

// Every output a script names (the EXR and PNG of `save`), checked against the scene's files
// before the window opens, so a script never renders and then fails on (or replaces) an input.
void Viewer::check_script_outputs() const {
  if (!script_) return;
  for (const auto& c : script_->script().commands) {
    if (c.args.empty() || (c.name != "save" && c.name != "save-scene" && c.name != "screenshot")) continue;
    try {
      const fs::path p = with_extension(c.args[0],
                                        c.name == "save"         ? ".exr"
                                        : c.name == "save-scene" ? ".json"
                                                                 : ".png",
                                        c.name);
      refuse_inputs(p, false, c.name);
      if (c.name == "save") {
        fs::path png = p;
        refuse_inputs(png.replace_extension(".png"), false, c.name + " (its PNG)");
      }
    } catch (const Error& e) {
      fail(fmt::format("{}: {}", script_->script().where(c), e.what()));
    }
  }
}

// ---------------------------------------------------------------- saving ---------------------

void Viewer::write_image(const fs::path& path, bool confirmed) {
  const fs::path exr = with_extension(path, ".exr", "save");
  fs::path png = exr;
  png.replace_extension(".png");
  refuse_inputs(exr, confirmed, "save");
  refuse_inputs(png, confirmed, "save (its PNG)");
  OutputTransaction tx;
  tx.add(exr);
  tx.add(png);
  const Image hdr = renderer_->accumulated();
  const scene::Camera& c = renderer_->camera();
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", original_.file.string()},
                        {"nearfield:source", "nearfield view"},
                        {"nearfield:content",
                         "linear radiance in the luminaires' units: W m^-2 sr^-1 (radiometric) or cd m^-2 "
                         "(photometric; render --stats names each luminaire's)"},
                        {"nearfield:gl_renderer", renderer_->gl_renderer()},
                        {"nearfield:frames", std::to_string(renderer_->frames())},
                        {"nearfield:samples", std::to_string(renderer_->total_times().samples)},
                        {"nearfield:camera", fmt::format("position {} {} {} target {} {} {} up {} {} {} fov_y {}",
                                                         c.position.x, c.position.y, c.position.z, c.target.x,
                                                         c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fov_y_deg)}};
  for (const auto& kv : units_.radiance_attributes()) attrs.push_back(kv);  // app/image_units.h
  for (const auto& kv : render::settings_attributes(renderer_->settings())) attrs.push_back(kv);
  write_exr(tx, exr, hdr, attrs);
  write_png(tx, png, renderer_->display_image());  // the device's 8-bit image, as shown
  tx.commit();
  status(fmt::format("saved {} and {} ({} frames)", exr.string(), png.string(), renderer_->frames()));
}

void Viewer::write_scene(const fs::path& path, bool confirmed) {
  const fs::path json = with_extension(path, ".json", "save-scene");
  refuse_inputs(json, confirmed, "save-scene");
  if (edited_instances_)
    fail(
        "save-scene: luminaire instances were added or deleted in the viewer; saving such a scene is not supported "
        "(the scene file's luminaires are matched by index)");
  scene::SceneState st;
  st.camera = state_.orbit.camera(render_width(), render_height());
  for (std::size_t i = 0; i < state_.lums.size(); ++i) {
    scene::LuminaireState l;
    l.to_world = state_.luminaire_matrix(i);
    l.intensity = state_.lums[i].intensity;
    l.has_euler = true;
    l.translate = state_.lums[i].translate;
    l.euler_deg = state_.lums[i].euler;
    st.luminaires.push_back(l);
  }
  st.render = render_settings(state_.settings.frame);
  st.materials = renderer_->scene().geometry.materials;  // as rendered (sync() pushed the edits)
  scene::save_scene(original_, st, json);
  status(fmt::format("saved {}", json.string()));
}

void Viewer::write_screenshot(const fs::path& path, bool confirmed) {
  const fs::path png = with_extension(path, ".png", "screenshot");
  refuse_inputs(png, confirmed, "screenshot");
  int w = 0, h = 0;
  window_->framebuffer_size(w, h);
  if (w <= 0 || h <= 0) fail("screenshot: the window has no pixels");
  std::vector<std::uint8_t> px(4 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        img.at(x, y, c) =
            px[4 * (static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) +
               static_cast<std::size_t>(c)] /
            255.0f;
  write_png(png, img);
  status(fmt::format("saved {}", png.string()));
}

void Viewer::request_save(const std::string& kind, const fs::path& path) {
  try {
    const std::string ext = kind == "scene" ? ".json" : kind == "image" ? ".exr" : ".png";
    const fs::path p = with_extension(path, ext, kind);
    refuse_inputs(p, true, kind);  // the scene's other files: never
    if (kind == "image") {
      fs::path png = p;
      refuse_inputs(png.replace_extension(".png"), true, kind);
    }
    std::error_code ec;
    fs::path other = p;
    other.replace_extension(".png");
    if (same_file(p, original_.file)) {
      state_.pending =
          PendingSave{kind, p, fmt::format("{} is the scene file being viewed.\nOverwrite it?", p.string())};
    } else if (fs::exists(p, ec) || (kind == "image" && fs::exists(other, ec))) {
      state_.pending = PendingSave{kind, p,
                                   fmt::format("{} already exists.\nOverwrite it?",
                                               kind == "image" && !fs::exists(p, ec) ? other.string() : p.string())};
    } else {
      perform_save(kind, p, false);
    }
  } catch (const Error& e) {
    status(e.what(), true);
  }
}

void Viewer::perform_save(const std::string& kind, const fs::path& path, bool confirmed) {
  try {
    if (kind == "image") write_image(path, confirmed);
    if (kind == "scene") write_scene(path, confirmed);
    if (kind == "screenshot") state_.capture = path;  // taken after this frame is drawn
  } catch (const Error& e) {
    status(e.what(), true);
  }
}

// ---------------------------------------------------------------- statistics -----------------

void Viewer::write_stats() {
  ViewerStats::Header h;
  h.scene = opt_.scene.string();
  window_->framebuffer_size(h.window_width, h.window_height);
  h.width = renderer_->camera().width;
  h.height = renderer_->camera().height;
  h.scale = state_.settings.scale;
  h.fast_motion = state_.settings.fast_motion;
  stats_.write(opt_.stats, h, render::to_json(renderer_->stats()));
}

}  // namespace nf::app
