// The viewer's Dear ImGui panel: settings, display, camera, luminaires, statistics, files,
// shortcuts (docs/viewer.md lists the same shortcuts).
#include "app/viewer_panel.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "app/settings_panel.h"
#include "render/frame_settings.h"
#include "render/stats.h"
#include "scene/material_json.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

struct Shortcut {
  const char* keys;
  const char* action;
};

const std::vector<Shortcut>& shortcut_table() {
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

// One draw of the panel: the state it edits, the loop's actions, what it shows.
struct Panel {
  ViewerState& s;
  ViewerActions& a;
  const PanelView& v;
  const render::Renderer& r;

  void draw();
  bool section(const char* title, const char* name, bool open_by_default);
  void combo(const char* label, const char* key, const std::string& current, const std::vector<std::string>& names);
  void settings(const std::vector<std::string>& only);
  void setting(const SettingWidget& w, const scene::RenderSettings& d);
  void header();
  void rendering();
  void display();
  void readout();
  void camera();
  void luminaires();
  void materials(bool open_all);
  void material(const scene::Material& m);
  void statistics();
  void footer_lines();
  void files();
  void shortcuts();
};

void Panel::draw() {
  const int fh = v.fb_height;
  const int docked = docked_panel_width(s, v.fb_width);
  ImGuiWindowFlags flags = 0;
  if (docked > 0) {  // docked: the window's left strip, full height; the image is beside it
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(static_cast<float>(docked), static_cast<float>(fh)), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(1.0f);
    flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse;
  } else {  // floating over the image, translucent, wherever the user puts it
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(400, static_cast<float>(std::max(fh - 16, 200))), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.85f);
  }
  if (ImGui::Begin("nearfield view", nullptr, flags)) {
    // The essentials stay visible below the sections, which scroll in their own region.
    const float footer = 3.0f * ImGui::GetTextLineHeightWithSpacing() + ImGui::GetStyle().ItemSpacing.y + 2.0f;
    ImGui::BeginChild("sections", ImVec2(0, -footer));
    ImGui::PushItemWidth(-190.0f);  // room for the labels
    header();
    if (section("Rendering", "rendering", true)) rendering();
    if (section("Display", "display", true)) display();
    if (section("Camera", "camera", false)) camera();
    if (section("Luminaires", "luminaires", false)) luminaires();
    const auto scripted = s.open_sections.find("materials");  // `section materials on` opens every entry too
    const bool open_all = scripted != s.open_sections.end() && scripted->second;
    if (section("Materials", "materials", false)) materials(open_all);
    if (section("Statistics", "statistics", true)) statistics();
    if (section("Files", "files", false)) files();
    if (section("Shortcuts", "shortcuts", false)) shortcuts();
    if (!s.status.empty()) {
      ImGui::Separator();
      const ImVec4 colour = s.status_error ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f) : ImVec4(0.6f, 0.9f, 0.6f, 1.0f);
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(colour, "%s", s.status.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::PopItemWidth();
    ImGui::EndChild();
    footer_lines();
  }
  ImGui::End();
}

// Always visible under the scrolling sections: frames, speed, the last frame's time.
void Panel::footer_lines() {
  ImGui::Separator();
  const render::StepTimes& t = v.stats.last_times();
  const double loop = v.stats.loop_ms_recent();
  ImGui::Text("%d frames, %lld spp | %.1f fps", r.frames(),
              static_cast<long long>(r.frames()) * s.settings.frame.sampling.spp, loop > 0 ? 1000.0 / loop : 0.0);
  const double seconds = v.stats.last_loop_ms() / 1000.0;
  ImGui::Text("renderer %.1f ms | %.3g samples/s", t.wall_ms,
              seconds > 0 ? static_cast<double>(t.samples) / seconds : 0.0);
  bool overlay = s.panel_overlay;
  if (ImGui::Checkbox("panel over the image", &overlay)) s.panel_overlay = overlay;
}

// A collapsing header; a scripted `section NAME on|off` opens or closes it once.
bool Panel::section(const char* title, const char* name, bool open_by_default) {
  const auto it = s.open_sections.find(name);
  if (it != s.open_sections.end()) {
    ImGui::SetNextItemOpen(it->second);
    s.open_sections.erase(it);
  }
  return ImGui::CollapsingHeader(title, open_by_default ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}

void Panel::header() {
  const scene::Camera& c = r.camera();
  const int fw = v.fb_width, fh = v.fb_height;
  ImGui::Text("%s", v.scene_name.c_str());
  ImGui::Text("%d x %d (window %d x %d, scale %.3g)", c.width, c.height, fw, fh, s.settings.scale);
  const int frames = r.frames();
  std::size_t surface = 0;
  for (const auto k : r.pixel_kinds()) surface += k == render::PixelKind::surface ? 1 : 0;
  const double actual = surface ? static_cast<double>(r.total_times().samples) / static_cast<double>(surface) : 0.0;
  ImGui::Text("accumulated: %d frames = %lld spp (K x frames)", frames,
              static_cast<long long>(frames) * s.settings.frame.sampling.spp);
  ImGui::Text("samples drawn: %.1f per surface pixel", actual);
  if (s.settings.paused) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "paused (Space)");
  if (s.settings.max_frames > 0 && frames >= s.settings.max_frames)
    ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "stopped at max frames");
  if (v.fast_active) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "moving: visibility off (fast motion)");
}

void Panel::combo(const char* label, const char* key, const std::string& current,
                  const std::vector<std::string>& names) {
  if (!ImGui::BeginCombo(label, current.c_str())) return;
  for (const auto& n : names)
    if (ImGui::Selectable(n.c_str(), n == current)) a.set(key, n);
  ImGui::EndCombo();
}

// The settings widgets, generated from the registry (app/settings_panel.h): the groups of the
// built contributions, each setting with its declared choices or range and its doc as tooltip.
void Panel::settings(const std::vector<std::string>& only) {
  std::vector<std::string> built;
  for (const auto& [name, frame] : r.contribution_rows()) built.push_back(name);
  const scene::RenderSettings d = render::render_settings(s.settings.frame);
  for (const auto& g : setting_widgets(built, only)) {
    if (only.empty()) {
      ImGui::Separator();
      ImGui::TextDisabled("%s", g.name.c_str());
    }
    for (const auto& w : g.widgets) setting(w, d);
  }
}

void Panel::setting(const SettingWidget& w, const scene::RenderSettings& d) {
  const scene::Setting& st = *w.setting;
  const std::string now = st.get(d);
  switch (st.type) {
    case scene::SettingType::choice:
      combo(st.name.c_str(), st.name.c_str(), now, w.choices);
      break;
    case scene::SettingType::integer: {
      const long long from = std::stoll(now);
      int value = static_cast<int>(from);
      if (ImGui::InputInt(st.name.c_str(), &value, 1, 16)) {
        const long long to = accepted_integer(st, d, from, value);
        if (to != from) a.set(st.name, std::to_string(to));
      }
      break;
    }
    case scene::SettingType::real: {
      double value = std::stod(now);
      if (ImGui::InputDouble(st.name.c_str(), &value, 0.0, 0.0, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue))
        a.set(st.name, fmt::format("{}", std::clamp(value, w.lo, w.hi)));  // > lo: the registry's message
      break;
    }
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s (%s)", st.doc.c_str(), st.range_text().c_str());
}

void Panel::rendering() {
  settings({});
  ImGui::Separator();
  float scale = static_cast<float>(s.settings.scale);
  if (ImGui::SliderFloat("resolution scale", &scale, static_cast<float>(kMinScale), 1.0f, "%.3f"))
    a.set("scale", fmt::format("{}", scale));
  ImGui::Checkbox("fast motion (F)", &s.settings.fast_motion);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("visibility 'none' while the camera or a luminaire moves");
  ImGui::SameLine();
  ImGui::Checkbox("pause", &s.settings.paused);
  int max_frames = s.settings.max_frames;
  if (ImGui::InputInt("max frames (0: none)", &max_frames))
    a.set("max_frames", std::to_string(std::max(max_frames, 0)));
  if (ImGui::Button("restart accumulation (C)")) a.restart();
}

// One collapsible entry per scene material; every change is an edit in the `material` script
// command's words (app/material_edit.h) through ViewerActions::material.
void Panel::materials(bool open_all) {
  if (s.materials.empty()) ImGui::TextDisabled("the scene has no materials");
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const scene::Material& m = s.materials[i];
    ImGui::PushID(static_cast<int>(i));
    if (open_all) ImGui::SetNextItemOpen(true);
    if (ImGui::TreeNode("material", "%s (%s)", m.name.c_str(), scene::material_kind_name(m.kind))) {
      material(m);
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
}

void Panel::material(const scene::Material& m) {
  const std::string name = m.name;  // `m` may change under an edit
  auto edit = [&](std::vector<std::string> words) { a.material(name, words); };
  auto num = [](float x) { return fmt::format("{}", x); };  // shortest text that reads back to x
  auto rgb = [&](const char* label, const glm::vec3& c, bool hdr, std::vector<std::string> head) {
    float rgb_v[3] = {c.r, c.g, c.b};
    const ImGuiColorEditFlags flags = ImGuiColorEditFlags_Float | (hdr ? ImGuiColorEditFlags_HDR : 0);
    if (ImGui::ColorEdit3(label, rgb_v, flags)) {
      for (float x : rgb_v) head.push_back(num(hdr ? std::max(x, 0.0f) : std::clamp(x, 0.0f, 1.0f)));
      edit(head);
    }
  };
  auto slider = [&](const char* label, float value, float lo, float hi, std::vector<std::string> head,
                    ImGuiSliderFlags flags = 0) {
    if (ImGui::SliderFloat(label, &value, lo, hi, "%.4g", flags | ImGuiSliderFlags_AlwaysClamp)) {
      head.push_back(num(value));
      edit(head);
    }
  };
  if (ImGui::BeginCombo("type", scene::material_kind_name(m.kind))) {
    for (const char* k : {"lambert", "ggx", "kurt"})
      if (ImGui::Selectable(k, k == std::string(scene::material_kind_name(m.kind)))) edit({"type", k});
    ImGui::EndCombo();
  }
  switch (m.kind) {
    case scene::MaterialKind::lambert:
    case scene::MaterialKind::ggx:
      rgb("base colour", m.base_color, false, {"base_color"});
      if (m.base_color_texture >= 0) ImGui::TextDisabled("(x texture %d)", m.base_color_texture);
      if (m.kind == scene::MaterialKind::ggx) {
        slider("metallic", m.metallic, 0.0f, 1.0f, {"metallic"});
        slider("roughness", m.roughness, 0.0f, 1.0f, {"roughness"});
      }
      break;
    case scene::MaterialKind::kurt: {
      rgb("k_d", m.base_color, false, {"diffuse"});
      for (std::size_t j = 0; j < m.kurt_lobes.size(); ++j) {
        const scene::KurtLobe l = m.kurt_lobes[j];
        const std::string js = std::to_string(j);
        ImGui::PushID(static_cast<int>(j));
        ImGui::Separator();
        ImGui::Text("lobe %zu", j);
        ImGui::SameLine();
        if (ImGui::SmallButton("remove")) {
          edit({"remove-lobe", js});  // the lobes shifted: draw them on the next frame
          ImGui::PopID();
          break;
        }
        rgb("k_s", l.ks, true, {"lobe", js, "ks"});
        slider("r0", l.r0, 0.0f, 1.0f, {"lobe", js, "r0"});
        slider("m_x", l.mx, 1e-3f, 1.0f, {"lobe", js, "mx"}, ImGuiSliderFlags_Logarithmic);
        slider("m_y", l.my, 1e-3f, 1.0f, {"lobe", js, "my"}, ImGuiSliderFlags_Logarithmic);
        slider("alpha", l.alpha, 0.0f, 1.0f, {"lobe", js, "alpha"});
        ImGui::PopID();
      }
      if (m.kurt_lobes.size() < 4 && ImGui::Button("add lobe")) edit({"add-lobe"});
      break;
    }
  }
}

void Panel::display() {
  DisplayMode mode = s.display;
  std::string view = mode == DisplayMode::debug ? s.debug_view : std::string();
  const std::vector<render::DebugViewInfo> offered = r.debug_views();  // of the built contributions
  const DisplayModeName* legend = nullptr;
  for (const auto& d : display_modes()) {
    const bool chosen = mode == d.mode && (d.mode != DisplayMode::debug || view == d.name);
    // a debug view needs its contribution; without it the image is shown
    if (d.mode == DisplayMode::debug &&
        std::none_of(offered.begin(), offered.end(), [&](const auto& o) { return o.name == d.name; })) {
      if (chosen) {
        mode = DisplayMode::image;
        view.clear();
      }
      continue;
    }
    if (ImGui::RadioButton(d.label.c_str(), chosen)) {
      mode = d.mode;
      view = d.mode == DisplayMode::debug ? d.name : std::string();
    }
    if (!d.tip.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", d.tip.c_str());
    ImGui::SameLine();
    if (d.mode == DisplayMode::debug && d.name == s.debug_view) legend = &d;
  }
  if (ImGui::Checkbox("log", &s.false_log)) s.redisplay = true;
  if (mode != s.display || view != s.debug_view) {
    s.display = mode;
    s.debug_view = view;
    s.redisplay = true;
  }
  if (s.display == DisplayMode::debug) {
    colour_bar(ImGui::GetContentRegionAvail().x, 12.0f);
    if (legend) ImGui::TextUnformatted(legend->legend.c_str());
  } else if (s.display != DisplayMode::image) {
    colour_bar(ImGui::GetContentRegionAvail().x, 12.0f);
    ImGui::Text("%s %.4g .. %.4g%s  (black: 0)", s.display == DisplayMode::a ? "A(p) [Y m^2]" : "K(p) [samples]",
                v.false_range.lo, v.false_range.hi, v.false_range.log_scale ? " (log)" : "");
  }
  settings({"display"});
  readout();
}

// Luminance (and illuminance, once computed for this view) under the cursor (viewer_readout.h).
void Panel::readout() {
  if (!v.readout || !v.units) return;
  ImGui::TextUnformatted("under the cursor:");
  ImGui::SameLine();
  ImGui::TextUnformatted(v.readout->inside ? v.readout->text(*v.units).c_str() : "-");
  if (ImGui::Button(v.has_illuminance ? "recompute illuminance" : "compute illuminance")) a.compute_illuminance();
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("white-Lambert render of this view (E = pi L; docs/photometry.md); kept until the view changes");
}

void Panel::camera() {
  glm::dvec3 pos = s.orbit.position(), target = s.orbit.target();
  bool changed = ImGui::InputScalarN("position", ImGuiDataType_Double, &pos.x, 3, nullptr, nullptr, "%.3f",
                                     ImGuiInputTextFlags_EnterReturnsTrue);
  changed |= ImGui::InputScalarN("target", ImGuiDataType_Double, &target.x, 3, nullptr, nullptr, "%.3f",
                                 ImGuiInputTextFlags_EnterReturnsTrue);
  if (changed) s.orbit.look_at(pos, target);
  ImGui::Text("distance %.3f m, yaw %.1f, pitch %.1f deg", s.orbit.distance(), s.orbit.yaw(), s.orbit.pitch());
  float fov = static_cast<float>(s.orbit.fov());
  if (ImGui::SliderFloat("fov y (deg)", &fov, 5.0f, 120.0f, "%.1f")) s.orbit.set_fov(fov);
  if (ImGui::Button("reset view (H)")) s.reset_view();
}

void Panel::luminaires() {
  if (s.lums.empty()) {
    ImGui::TextUnformatted("no luminaire instances: the image is black");
    ImGui::TextDisabled("script: instance add NAME PRESET X Y Z [YAW]");
    return;
  }
  s.selected = std::clamp(s.selected, 0, static_cast<int>(s.lums.size()) - 1);
  const std::size_t i = static_cast<std::size_t>(s.selected);
  auto label = [this](std::size_t k) {
    return fmt::format("{}: {}", k, k < s.lum_names.size() ? s.lum_names[k] : std::string());
  };
  if (ImGui::BeginCombo("luminaire (N)", label(i).c_str())) {
    for (std::size_t k = 0; k < s.lums.size(); ++k)
      if (ImGui::Selectable(label(k).c_str(), k == i)) s.selected = static_cast<int>(k);
    ImGui::EndCombo();
  }
  LuminaireEdit& e = s.lums[static_cast<std::size_t>(s.selected)];
  ImGui::DragScalarN("translate (m)", ImGuiDataType_Double, &e.translate.x, 3, 0.01f, nullptr, nullptr, "%.3f");
  ImGui::DragScalarN("rotate (deg)", ImGuiDataType_Double, &e.euler.x, 3, 0.5f, nullptr, nullptr, "%.2f");
  const double zero = 0.0, big = scene::kMaxIntensity;  // the scene's rule
  ImGui::DragScalar("intensity", ImGuiDataType_Double, &e.intensity, 0.01f, &zero, &big, "%.3f");
  e.intensity = std::max(e.intensity, 0.0);
  if (ImGui::Button("reset luminaire")) s.reset_luminaire(static_cast<std::size_t>(s.selected));
  // Instances come and go (only the new one's shadow maps are rendered; the accumulation restarts).
  ImGui::SameLine();
  if (ImGui::Button("duplicate")) {
    LuminaireEdit copy = e;
    copy.translate.x += 0.5;
    std::string name = s.lum_names[i] + " copy";
    while (std::find(s.lum_names.begin(), s.lum_names.end(), name) != s.lum_names.end()) name += "'";
    s.add_instance(name, s.lum_names[i], copy);
    return;
  }
  ImGui::SameLine();
  if (ImGui::Button("delete")) {
    s.delete_instance(i);
    return;
  }
  ImGui::TextDisabled("rotate [rx, ry, rz]: R = Rz Ry Rx, as in scenes");
  ImGui::TextDisabled("Ctrl+left drag: move; Ctrl+right drag: turn");
}

void Panel::statistics() {
  const render::StepTimes& t = v.stats.last_times();
  ImGui::Text("%.1f fps (%.1f ms per loop, renderer %.1f ms)",
              v.stats.loop_ms_recent() > 0 ? 1000.0 / v.stats.loop_ms_recent() : 0.0, v.stats.loop_ms_recent(),
              t.wall_ms);
  if (!v.stats.fps_history().empty()) {
    std::vector<float> fps(v.stats.fps_history().begin(), v.stats.fps_history().end());
    ImGui::PlotLines("##fps", fps.data(), static_cast<int>(fps.size()), 0, "fps", 0.0f, FLT_MAX,
                     ImVec2(ImGui::GetContentRegionAvail().x, 40));
  }
  const double seconds = v.stats.last_loop_ms() / 1000.0;
  ImGui::Text("%.3g samples/s (%llu samples last frame)", seconds > 0 ? static_cast<double>(t.samples) / seconds : 0.0,
              static_cast<unsigned long long>(t.samples));
  if (t.step0_runs > 0)
    ImGui::Text("Step 0: %.1f ms (G-buffer %.1f, shadow maps %.1f,\n        visibility %.1f)", t.step0_ms(),
                t.gbuffer_ms + t.gbuffer_readback_ms, t.shadow_maps_ms, t.visibility_ms);
  else
    ImGui::TextUnformatted("Step 0: skipped (camera and luminaires unchanged)");
  const render::Breakdown b = render::fig10_breakdown(t);
  const int frames = std::max(r.frames(), 1);
  const render::Breakdown m = render::fig10_breakdown(r.total_times());
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
  if (ImGui::BeginTable("contributions", 4, ImGuiTableFlags_BordersInnerH | ImGuiTableFlags_SizingStretchProp)) {
    ImGui::TableSetupColumn("contribution");
    ImGui::TableSetupColumn("build/A ms");
    ImGui::TableSetupColumn("shade ms");
    ImGui::TableSetupColumn("readback ms");
    ImGui::TableHeadersRow();
    for (const auto& [name, f] : r.contribution_rows()) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", f.step1_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", f.step2_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", f.readback_ms);
      for (const auto& [part, ms] : f.parts_ms) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::Text("  %s", part.c_str());
        ImGui::TableNextColumn();
        ImGui::Text("%.2f", ms);
      }
    }
    ImGui::EndTable();
  }
  ImGui::Text("mean over %d frames: %.1f ms\n  (est. A %.1f, sampling + shading %.1f, shadow %.1f)", r.frames(),
              m.total() / frames, m.a_estimation / frames, m.sampling_shading / frames, m.shadow / frames);
  const auto mem = r.memory();
  std::size_t total = 0;
  for (const auto& item : mem) total += item.bytes;
  if (ImGui::TreeNode("memory", "memory: %.1f MiB in %zu buffers", mib(total), mem.size())) {
    for (const auto& item : mem) ImGui::BulletText("%.2f MiB  %s", mib(item.bytes), item.name.c_str());
    ImGui::TreePop();
  }
}

void Panel::files() {
  ImGui::InputText("image (.exr)", &s.image_path);
  if (ImGui::Button("save image: EXR + PNG (Ctrl+S)")) a.request_save("image", s.image_path);
  ImGui::InputText("scene (.json)", &s.scene_path);
  if (ImGui::Button("save view as scene (Ctrl+Shift+S)")) a.request_save("scene", s.scene_path);
  ImGui::InputText("window (.png)", &s.screenshot_path);
  if (ImGui::Button("save window (F12)")) a.request_save("screenshot", s.screenshot_path);
}

void Panel::shortcuts() {
  if (!ImGui::BeginTable("keys", 2, ImGuiTableFlags_BordersInnerH | ImGuiTableFlags_SizingStretchProp)) return;
  for (const auto& k : shortcut_table()) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(k.keys);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(k.action);
  }
  ImGui::EndTable();
}

}  // namespace

int docked_panel_width(const ViewerState& s, int fb_width) {
  if (!s.panel || s.panel_overlay) return 0;
  return std::min(400, fb_width / 2);
}

void draw_panel(ViewerState& s, ViewerActions& actions, const PanelView& view) {
  Panel{s, actions, view, view.renderer}.draw();
}

void draw_confirm_popup(ViewerState& s, ViewerActions& a) {
  if (!s.pending) return;
  if (!ImGui::IsPopupOpen("confirm")) ImGui::OpenPopup("confirm");
  if (!ImGui::BeginPopupModal("confirm", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::TextUnformatted(s.pending->question.c_str());
  if (ImGui::Button("overwrite")) {
    const PendingSave p = *s.pending;
    s.pending.reset();
    ImGui::CloseCurrentPopup();
    a.perform_save(p.kind, p.path, true);
  }
  ImGui::SameLine();
  if (ImGui::Button("cancel") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false)) {
    s.pending.reset();
    ImGui::CloseCurrentPopup();
    a.status("not saved");
  }
  ImGui::EndPopup();
}

}  // namespace nf::app
