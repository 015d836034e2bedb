// The viewer's Dear ImGui panel: settings, display, camera, luminaires, statistics, files,
// shortcuts (docs/viewer.md lists the same shortcuts).
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "app/viewer_impl.h"
#include "render/stats.h"

namespace nf::app {
namespace {

struct Shortcut {
  const char* keys;
  const char* action;
};

const std::vector<Shortcut>& shortcuts() {
  static const std::vector<Shortcut> s{
      {"Left drag", "orbit about the target"},
      {"Right / middle drag, Shift+left drag", "pan"},
      {"Wheel, PgUp / PgDn", "zoom (eye distance)"},
      {"Arrows", "orbit by 5 degrees"},
      {"Ctrl+left drag", "move the selected luminaire in the view plane"},
      {"Ctrl+right drag", "turn the selected luminaire"},
      {"N", "select the next luminaire"},
      {"H, Home", "reset the view"},
      {"Space", "pause / resume accumulation"},
      {"C", "restart the accumulation"},
      {"D", "display: image, A(p), K(p)"},
      {"V", "visibility: shadowmaps / none"},
      {"F", "fast motion (visibility none while moving)"},
      {"+ / -", "exposure x1.25 / /1.25"},
      {"] / [", "spp K x2 / /2"},
      {". / ,", "resolution scale x1.25 / /1.25"},
      {"Ctrl+S", "save the image (EXR + PNG)"},
      {"Ctrl+Shift+S", "save the view as a scene file"},
      {"F12", "save the window (PNG)"},
      {"Tab, F1", "show / hide this panel"},
      {"Esc, Q", "quit"},
  };
  return s;
}

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

// A horizontal bar of the false-colour ramp.
void colour_bar(float width, float height) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const int n = 32;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 a = colour_map(static_cast<double>(i) / n), b = colour_map(static_cast<double>(i + 1) / n);
    const ImU32 ca = ImGui::GetColorU32(ImVec4(a.r, a.g, a.b, 1.0f)),
                cb = ImGui::GetColorU32(ImVec4(b.r, b.g, b.b, 1.0f));
    const float x0 = p.x + width * static_cast<float>(i) / n, x1 = p.x + width * static_cast<float>(i + 1) / n;
    dl->AddRectFilledMultiColor(ImVec2(x0, p.y), ImVec2(x1, p.y + height), ca, cb, cb, ca);
  }
  ImGui::Dummy(ImVec2(width, height));
}

void breakdown_row(const char* name, double ms, double total) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(name);
  ImGui::TableNextColumn();
  ImGui::Text("%.1f", ms);
  ImGui::TableNextColumn();
  ImGui::Text("%.1f %%", total > 0 ? 100.0 * ms / total : 0.0);
}

}  // namespace

void Viewer::draw_panel() {
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(400, static_cast<float>(std::max(fh - 16, 200))), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (ImGui::Begin("nearfield view")) {
    ImGui::PushItemWidth(-190.0f);  // room for the labels
    panel_header();
    if (section("Rendering", "rendering", true)) panel_rendering();
    if (section("Display", "display", true)) panel_display();
    if (section("Camera", "camera", false)) panel_camera();
    if (section("Luminaires", "luminaires", false)) panel_luminaires();
    if (section("Statistics", "statistics", true)) panel_statistics();
    if (section("Files", "files", false)) panel_files();
    if (section("Shortcuts", "shortcuts", false)) panel_shortcuts();
    if (!status_.empty()) {
      ImGui::Separator();
      const ImVec4 colour = status_error_ ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f) : ImVec4(0.6f, 0.9f, 0.6f, 1.0f);
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(colour, "%s", status_.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::PopItemWidth();
  }
  ImGui::End();
}

// A collapsing header; a scripted `section NAME on|off` opens or closes it once.
bool Viewer::section(const char* title, const char* name, bool open_by_default) {
  const auto it = open_sections_.find(name);
  if (it != open_sections_.end()) {
    ImGui::SetNextItemOpen(it->second);
    open_sections_.erase(it);
  }
  return ImGui::CollapsingHeader(title, open_by_default ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}

void Viewer::panel_header() {
  const scene::Camera& c = renderer_->camera();
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  ImGui::Text("%s", opt_.scene.filename().string().c_str());
  ImGui::Text("%d x %d (window %d x %d, scale %.3g)", c.width, c.height, fw, fh, settings_.scale);
  const int frames = renderer_->frames();
  std::size_t surface = 0;
  for (const auto k : renderer_->pixel_kinds()) surface += k == render::PixelKind::surface ? 1 : 0;
  const double actual =
      surface ? static_cast<double>(renderer_->total_times().samples) / static_cast<double>(surface) : 0.0;
  ImGui::Text("accumulated: %d frames = %lld spp (K x frames)", frames,
              static_cast<long long>(frames) * settings_.frame.sampling.spp);
  ImGui::Text("samples drawn: %.1f per surface pixel", actual);
  if (settings_.paused) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "paused (Space)");
  if (settings_.max_frames > 0 && frames >= settings_.max_frames)
    ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "stopped at max frames");
  if (fast_active_) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "moving: visibility off (fast motion)");
}

void Viewer::combo(const char* label, const char* key, const std::string& current,
                   const std::vector<std::string>& names) {
  if (!ImGui::BeginCombo(label, current.c_str())) return;
  for (const auto& n : names)
    if (ImGui::Selectable(n.c_str(), n == current)) set(key, n);
  ImGui::EndCombo();
}

void Viewer::panel_rendering() {
  const render::FrameSettings& f = settings_.frame;
  const render::SamplingSettings& p = f.sampling;
  combo("method", "method", render::to_string(p.method), render::method_names());
  combo("sampler", "sampler", render::to_string(p.sampler), render::sampler_names());
  int spp = p.spp;
  if (ImGui::InputInt("spp K / frame", &spp, 1, 16)) set("spp", std::to_string(std::max(spp, 1)));
  int kmax = p.k_max;
  if (ImGui::InputInt("K_max (0: none)", &kmax, 1, 16)) set("kmax", std::to_string(std::max(kmax, 0)));
  combo("balance", "balance", render::to_string(p.balance), render::balance_names());
  combo("search", "search", render::to_string(p.search), render::search_names());
  int depth = p.search_depth;
  if (ImGui::InputInt("search depth (-1: exact)", &depth)) {
    if (depth == 0) depth = p.search_depth < 0 ? 1 : -1;  // 0 is not a depth: step over it
    set("search_depth", std::to_string(std::clamp(depth, -1, 1024)));
  }
  combo("structure", "structure", render::to_string(p.structure), render::structure_names());
  combo("visibility", "visibility", render::to_string(f.visibility), {"none", "shadowmaps"});
  int sms = f.shadow_map_size;
  if (ImGui::InputInt("shadow map size", &sms, 16, 128))
    set("shadow_map_size", std::to_string(std::clamp(sms, 16, 4096)));
  int seed = static_cast<int>(p.seed);
  if (ImGui::InputInt("seed", &seed)) set("seed", std::to_string(std::max(seed, 0)));
  float scale = static_cast<float>(settings_.scale);
  if (ImGui::SliderFloat("resolution scale", &scale, static_cast<float>(kMinScale), 1.0f, "%.3f"))
    set("scale", fmt::format("{}", scale));
  ImGui::Checkbox("fast motion (F)", &settings_.fast_motion);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("visibility 'none' while the camera or a luminaire moves");
  ImGui::SameLine();
  ImGui::Checkbox("pause", &settings_.paused);
  int max_frames = settings_.max_frames;
  if (ImGui::InputInt("max frames (0: none)", &max_frames)) set("max_frames", std::to_string(std::max(max_frames, 0)));
  if (ImGui::Button("restart accumulation (C)")) renderer_->reset();
}

void Viewer::panel_display() {
  int mode = static_cast<int>(display_);
  ImGui::RadioButton("image", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("A(p)", &mode, 1);
  ImGui::SameLine();
  ImGui::RadioButton("K(p)", &mode, 2);
  ImGui::SameLine();
  if (ImGui::Checkbox("log", &false_log_)) redisplay_ = true;
  if (mode != static_cast<int>(display_)) {
    display_ = static_cast<DisplayMode>(mode);
    redisplay_ = true;
  }
  if (display_ != DisplayMode::image) {
    colour_bar(ImGui::GetContentRegionAvail().x, 12.0f);
    ImGui::Text("%s %.4g .. %.4g%s  (black: 0)", display_ == DisplayMode::a ? "A(p) [Y m^2]" : "K(p) [samples]",
                false_range_.lo, false_range_.hi, false_range_.log_scale ? " (log)" : "");
  }
  float exposure = static_cast<float>(settings_.frame.tonemap.exposure);
  if (ImGui::SliderFloat("exposure", &exposure, 0.01f, 100.0f, "%.3f", ImGuiSliderFlags_Logarithmic))
    set("exposure", fmt::format("{}", std::max(exposure, 1e-4f)));
  float gamma = static_cast<float>(settings_.frame.tonemap.gamma);
  if (ImGui::SliderFloat("gamma", &gamma, 0.5f, 4.0f, "%.2f")) set("gamma", fmt::format("{}", std::max(gamma, 0.05f)));
}

void Viewer::panel_camera() {
  glm::dvec3 pos = orbit_.position(), target = orbit_.target();
  bool changed = ImGui::InputScalarN("position", ImGuiDataType_Double, &pos.x, 3, nullptr, nullptr, "%.3f",
                                     ImGuiInputTextFlags_EnterReturnsTrue);
  changed |= ImGui::InputScalarN("target", ImGuiDataType_Double, &target.x, 3, nullptr, nullptr, "%.3f",
                                 ImGuiInputTextFlags_EnterReturnsTrue);
  if (changed) orbit_.look_at(pos, target);
  ImGui::Text("distance %.3f m, yaw %.1f, pitch %.1f deg", orbit_.distance(), orbit_.yaw(), orbit_.pitch());
  float fov = static_cast<float>(orbit_.fov());
  if (ImGui::SliderFloat("fov y (deg)", &fov, 5.0f, 120.0f, "%.1f")) orbit_.set_fov(fov);
  if (ImGui::Button("reset view (H)")) reset_view();
}

void Viewer::panel_luminaires() {
  if (lums_.empty()) {
    ImGui::TextUnformatted("the scene has no luminaires");
    return;
  }
  selected_ = std::clamp(selected_, 0, static_cast<int>(lums_.size()) - 1);
  const std::size_t i = static_cast<std::size_t>(selected_);
  auto label = [this](std::size_t k) { return fmt::format("{}: {}", k, renderer_->luminaire(k).name); };
  if (ImGui::BeginCombo("luminaire (N)", label(i).c_str())) {
    for (std::size_t k = 0; k < lums_.size(); ++k)
      if (ImGui::Selectable(label(k).c_str(), k == i)) selected_ = static_cast<int>(k);
    ImGui::EndCombo();
  }
  LuminaireEdit& e = lums_[static_cast<std::size_t>(selected_)];
  ImGui::DragScalarN("translate (m)", ImGuiDataType_Double, &e.translate.x, 3, 0.01f, nullptr, nullptr, "%.3f");
  ImGui::DragScalarN("rotate (deg)", ImGuiDataType_Double, &e.euler.x, 3, 0.5f, nullptr, nullptr, "%.2f");
  const double zero = 0.0, big = 1e6;
  ImGui::DragScalar("intensity", ImGuiDataType_Double, &e.intensity, 0.01f, &zero, &big, "%.3f");
  e.intensity = std::max(e.intensity, 0.0);
  if (ImGui::Button("reset luminaire")) reset_luminaire(static_cast<std::size_t>(selected_));
  ImGui::TextDisabled("rotate [rx, ry, rz]: R = Rz Ry Rx, as in scenes");
  ImGui::TextDisabled("Ctrl+left drag: move; Ctrl+right drag: turn");
}

void Viewer::panel_statistics() {
  const render::StepTimes& t = last_times_;
  ImGui::Text("%.1f fps (%.1f ms per loop, renderer %.1f ms)", loop_ms_recent_ > 0 ? 1000.0 / loop_ms_recent_ : 0.0,
              loop_ms_recent_, t.wall_ms);
  if (!fps_history_.empty()) {
    std::vector<float> v(fps_history_.begin(), fps_history_.end());
    ImGui::PlotLines("##fps", v.data(), static_cast<int>(v.size()), 0, "fps", 0.0f, FLT_MAX,
                     ImVec2(ImGui::GetContentRegionAvail().x, 40));
  }
  const double seconds = last_loop_ms_ / 1000.0;
  ImGui::Text("%.3g samples/s (%llu samples last frame)", seconds > 0 ? static_cast<double>(t.samples) / seconds : 0.0,
              static_cast<unsigned long long>(t.samples));
  if (t.step0_runs > 0)
    ImGui::Text("Step 0: %.1f ms (G-buffer %.1f, shadow maps %.1f,\n        visibility %.1f)", t.step0_ms(),
                t.gbuffer_ms + t.gbuffer_readback_ms, t.shadow_maps_ms, t.visibility_ms);
  else
    ImGui::TextUnformatted("Step 0: skipped (camera and luminaires unchanged)");
  const render::Breakdown b = render::fig10_breakdown(t);
  const int frames = std::max(renderer_->frames(), 1);
  const render::Breakdown m = render::fig10_breakdown(renderer_->total_times());
  if (ImGui::BeginTable("fig10", 3, ImGuiTableFlags_BordersInnerH | ImGuiTableFlags_SizingStretchProp)) {
    ImGui::TableSetupColumn("last frame (Fig. 10)");
    ImGui::TableSetupColumn("ms");
    ImGui::TableSetupColumn("share");
    ImGui::TableHeadersRow();
    breakdown_row("est. A (Step 1)", b.a_estimation, b.total());
    breakdown_row("sampling + shading", b.sampling_shading, b.total());
    breakdown_row("shadow", b.shadow, b.total());
    breakdown_row("accumulation", b.accumulation, b.total());
    breakdown_row("other", b.other, b.total());
    breakdown_row("total", b.total(), b.total());
    ImGui::EndTable();
  }
  ImGui::Text("mean over %d frames: %.1f ms\n  (est. A %.1f, sampling + shading %.1f, shadow %.1f)",
              renderer_->frames(), m.total() / frames, m.a_estimation / frames, m.sampling_shading / frames,
              m.shadow / frames);
  const auto mem = renderer_->memory();
  std::size_t total = 0;
  for (const auto& item : mem) total += item.bytes;
  if (ImGui::TreeNode("memory", "memory: %.1f MiB in %zu buffers", mib(total), mem.size())) {
    for (const auto& item : mem) ImGui::BulletText("%.2f MiB  %s", mib(item.bytes), item.name.c_str());
    ImGui::TreePop();
  }
}

void Viewer::panel_files() {
  ImGui::InputText("image (.exr)", &image_path_);
  if (ImGui::Button("save image: EXR + PNG (Ctrl+S)")) request_save("image", image_path_);
  ImGui::InputText("scene (.json)", &scene_path_);
  if (ImGui::Button("save view as scene (Ctrl+Shift+S)")) request_save("scene", scene_path_);
  ImGui::InputText("window (.png)", &screenshot_path_);
  if (ImGui::Button("save window (F12)")) request_save("screenshot", screenshot_path_);
}

void Viewer::panel_shortcuts() {
  if (!ImGui::BeginTable("keys", 2, ImGuiTableFlags_BordersInnerH | ImGuiTableFlags_SizingStretchProp)) return;
  for (const auto& s : shortcuts()) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(s.keys);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(s.action);
  }
  ImGui::EndTable();
}

void Viewer::confirm_popup() {
  if (!pending_) return;
  if (!ImGui::IsPopupOpen("confirm")) ImGui::OpenPopup("confirm");
  if (!ImGui::BeginPopupModal("confirm", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::TextUnformatted(pending_->question.c_str());
  if (ImGui::Button("overwrite")) {
    const PendingSave p = *pending_;
    pending_.reset();
    ImGui::CloseCurrentPopup();
    perform_save(p.kind, p.path, true);
  }
  ImGui::SameLine();
  if (ImGui::Button("cancel") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false)) {
    pending_.reset();
    ImGui::CloseCurrentPopup();
    status("not saved");
  }
  ImGui::EndPopup();
}

}  // namespace nf::app
