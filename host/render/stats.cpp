#include "render/stats.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace nf::render {

using json = nlohmann::ordered_json;

double StepTimes::cl_other_ms() const { return std::max(0.0, sampler_wall_ms - step1_ms - step2_ms); }

StepTimes& StepTimes::operator+=(const StepTimes& o) {
  gbuffer_ms += o.gbuffer_ms;
  gbuffer_readback_ms += o.gbuffer_readback_ms;
  shadow_maps_ms += o.shadow_maps_ms;
  visibility_ms += o.visibility_ms;
  luminaire_view_ms += o.luminaire_view_ms;
  surfaces_upload_ms += o.surfaces_upload_ms;
  visibility_upload_ms += o.visibility_upload_ms;
  step1_ms += o.step1_ms;
  step2_ms += o.step2_ms;
  sampler_wall_ms += o.sampler_wall_ms;
  readback_ms += o.readback_ms;
  accumulate_ms += o.accumulate_ms;
  step3_ms += o.step3_ms;
  wall_ms += o.wall_ms;
  build_ms += o.build_ms;
  samples += o.samples;
  frames += o.frames;
  step0_runs += o.step0_runs;
  shadow_map_runs += o.shadow_map_runs;
  tonemaps += o.tonemaps;
  return *this;
}

Breakdown fig10_breakdown(const StepTimes& t) {
  Breakdown b;
  b.a_estimation = t.step1_ms;
  b.sampling_shading = t.step2_ms;
  b.shadow = t.shadow_maps_ms + t.visibility_ms + t.visibility_upload_ms;
  b.accumulation = t.readback_ms + t.accumulate_ms;
  b.other = std::max(0.0, t.wall_ms - (b.a_estimation + b.sampling_shading + b.shadow + b.accumulation));
  return b;
}

namespace {

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

json steps_json(const StepTimes& t) {
  const Breakdown b = fig10_breakdown(t);
  const double total = b.total() > 0 ? b.total() : 1.0;
  json j;
  j["frames"] = t.frames;
  j["step0_runs"] = t.step0_runs;
  j["shadow_map_runs"] = t.shadow_map_runs;
  j["samples"] = t.samples;
  j["wall_ms"] = round3(t.wall_ms);
  j["build_ms"] = round3(t.build_ms);
  j["steps_ms"] = {{"step0", round3(t.step0_ms())},
                   {"step1", round3(t.step1_ms)},
                   {"step2", round3(t.step2_ms)},
                   {"cl_other", round3(t.cl_other_ms())},
                   {"accumulation", round3(t.readback_ms + t.accumulate_ms)},
                   {"step3", round3(t.step3_ms)}};
  j["step0_ms"] = {{"gbuffer", round3(t.gbuffer_ms)},
                   {"gbuffer_readback", round3(t.gbuffer_readback_ms)},
                   {"shadow_maps", round3(t.shadow_maps_ms)},
                   {"visibility", round3(t.visibility_ms)},
                   {"luminaire_view", round3(t.luminaire_view_ms)},
                   {"surfaces_upload", round3(t.surfaces_upload_ms)},
                   {"visibility_upload", round3(t.visibility_upload_ms)}};
  j["steps12_ms"] = {{"step1_kernels", round3(t.step1_ms)},
                     {"step2_kernels", round3(t.step2_ms)},
                     {"sampler_wall", round3(t.sampler_wall_ms)}};
  j["accumulation_ms"] = {{"readback", round3(t.readback_ms)}, {"accumulate", round3(t.accumulate_ms)}};
  j["fig10_ms"] = {{"a_estimation", round3(b.a_estimation)},
                   {"sampling_shading", round3(b.sampling_shading)},
                   {"shadow", round3(b.shadow)},
                   {"accumulation", round3(b.accumulation)},
                   {"other", round3(b.other)}};
  j["fig10_percent"] = {{"a_estimation", round3(100.0 * b.a_estimation / total)},
                        {"sampling_shading", round3(100.0 * b.sampling_shading / total)},
                        {"shadow", round3(100.0 * b.shadow / total)},
                        {"accumulation", round3(100.0 * b.accumulation / total)},
                        {"other", round3(100.0 * b.other / total)}};
  return j;
}

}  // namespace

std::string to_json(const RenderStats& s, const std::vector<std::pair<std::string, double>>& phases) {
  json j;
  j["format"] = "nearfield-render-stats";
  j["version"] = 1;
  j["cl_device"] = s.cl_device;
  j["cl_device_detail"] = s.cl_device_detail;
  j["gl_renderer"] = s.gl_renderer;
  j["resolution"] = {s.width, s.height};
  json settings = json::object();
  for (const auto& [k, v] : s.settings) settings[k] = v;
  j["settings"] = settings;
  json lums = json::array();
  for (const auto& l : s.luminaires)
    lums.push_back({{"source", l.label},
                    {"instances", l.instances},
                    {"images", l.images},
                    {"image_resolution", {l.res_x, l.res_y}},
                    {"channels", l.channels},
                    {"chroma", l.chroma},
                    {"units", l.units},
                    {"radiance_unit", l.radiance_unit},
                    {"load_ms", round3(l.load_ms)},
                    {"precompute_ms", round3(l.precompute_ms)},
                    {"device_bytes", l.device_bytes}});
  j["luminaires"] = lums;
  json contribs = json::array();
  for (const auto& c : s.contributions) {
    json parts = json::object();
    for (const auto& [name, ms] : c.parts_ms) parts[name] = round3(ms);
    contribs.push_back({{"name", c.name},
                        {"step1_ms", c.step1_ms},
                        {"step2_ms", c.step2_ms},
                        {"wall_ms", c.wall_ms},
                        {"readback_ms", c.readback_ms},
                        {"total_ms", c.total_ms},
                        {"samples", c.samples},
                        {"device_bytes", c.device_bytes},
                        {"parts_ms", parts}});
  }
  j["contributions"] = contribs;
  j["pixels"] = {{"total", s.pixels.total},
                 {"surface", s.pixels.surface},
                 {"luminaire", s.pixels.luminaire},
                 {"lit", s.pixels.lit}};
  const double frames = std::max(1, s.total.frames);
  j["samples"] = {
      {"total", s.total.samples},
      {"per_frame", static_cast<double>(s.total.samples) / frames},
      {"per_surface_pixel_per_frame",
       s.pixels.surface ? static_cast<double>(s.total.samples) / frames / static_cast<double>(s.pixels.surface) : 0.0},
      {"per_lit_pixel_per_frame",
       s.pixels.lit ? static_cast<double>(s.total.samples) / frames / static_cast<double>(s.pixels.lit) : 0.0}};
  j["first_frame"] = steps_json(s.first_frame);
  j["total"] = steps_json(s.total);
  json mem = json::array();
  std::size_t bytes = 0;
  for (const auto& m : s.memory) {
    mem.push_back({{"buffer", m.name}, {"bytes", m.bytes}});
    bytes += m.bytes;
  }
  j["memory"] = mem;
  j["memory_total_bytes"] = bytes;
  json ph = json::object();
  for (const auto& [k, v] : phases) ph[k] = round3(v);
  j["phases_ms"] = ph;
  return j.dump(2) + "\n";
}

namespace {

// Per frame, what a contribution's samples are counted against (docs/rendering.md, "Outputs"):
// the light fields draw K(p) per lit pixel (A(p) > 0); the others a fixed number per pixel of the
// frame, background included (far field: one per light, environment: its N, indirect: one per
// VSGL).
std::string samples_text(const RenderStats& s, const ContributionStats& c) {
  if (c.name == "luminaires")
    return s.pixels.lit ? fmt::format("{} ({:.1f} per lit pixel; {} of {} surface pixels lit)", c.samples,
                                      static_cast<double>(c.samples) / static_cast<double>(s.pixels.lit), s.pixels.lit,
                                      s.pixels.surface)
                        : fmt::format("{} (no surface pixel lit)", c.samples);
  return s.pixels.total ? fmt::format("{} ({:.1f} per pixel)", c.samples,
                                      static_cast<double>(c.samples) / static_cast<double>(s.pixels.total))
                        : fmt::format("{} (no pixel)", c.samples);
}

}  // namespace

std::string summary(const RenderStats& s) {
  const StepTimes& t = s.total;
  const StepTimes& last = s.last_frame;
  std::size_t bytes = 0;
  for (const auto& m : s.memory) bytes += m.bytes;
  std::string out;
  out += fmt::format("{}x{}, {} frame(s), {} samples, {} surface pixels, device {}\n", s.width, s.height, t.frames,
                     t.samples, s.pixels.surface, s.cl_device);
  // Samples of the last frame, per contribution (the sum over all frames is the line above).
  std::string samples;
  for (const auto& c : s.contributions)
    samples += fmt::format("{}{} {}", samples.empty() ? "" : " | ", c.name, samples_text(s, c));
  out += "samples (last frame): " + (samples.empty() ? std::string("none: the scene has no light source") : samples) +
         "\n";
  out += fmt::format(
      "steps (ms): 0 (GL G-buffer, shadows) {:.1f} | 1 (A) {:.1f} | 2 (sample+shade) {:.1f} | CL other {:.1f} | "
      "accumulation {:.1f} | 3 (tone map) {:.1f} | wall {:.1f}\n",
      t.step0_ms(), t.step1_ms, t.step2_ms, t.cl_other_ms(), t.readback_ms + t.accumulate_ms, t.step3_ms, t.wall_ms);
  // Where the last frame's wall time went, by part: Step 0, each contribution as a whole (its own
  // builds, kernels, readback), the accumulation, Step 3, the rest.
  if (last.wall_ms > 0) {
    const double wall = last.wall_ms;
    double named = last.step0_ms() + last.accumulate_ms + last.step3_ms;
    std::string parts = fmt::format("Step 0 {:.1f}%", 100 * last.step0_ms() / wall);
    for (const auto& c : s.contributions) {
      parts += fmt::format(" | {} {:.1f}%", c.name, 100 * c.total_ms / wall);
      named += c.total_ms;
    }
    parts += fmt::format(" | accumulation {:.1f}% | tone map {:.1f}% | other {:.1f}%", 100 * last.accumulate_ms / wall,
                         100 * last.step3_ms / wall, 100 * std::max(0.0, wall - named) / wall);
    out += fmt::format("last frame {:.1f} ms: {}\n", wall, parts);
  }
  // Lu et al. 2015 Fig. 10 is the light fields' breakdown: only with light-field luminaires.
  if (!s.luminaires.empty()) {
    const Breakdown b = fig10_breakdown(t);
    const double total = b.total() > 0 ? b.total() : 1.0;
    out += fmt::format(
        "Fig. 10 breakdown: A estimation {:.1f}% | sampling+shading {:.1f}% | shadow {:.1f}% | accumulation {:.1f}% | "
        "other {:.1f}%\n",
        100 * b.a_estimation / total, 100 * b.sampling_shading / total, 100 * b.shadow / total,
        100 * b.accumulation / total, 100 * b.other / total);
  }
  for (const auto& l : s.luminaires)
    out += fmt::format(
        "luminaire {}: {} instance(s), {} images of {}x{}, {} ({}), load {:.1f} ms, precompute {:.1f} ms, {:.1f} "
        "MiB\n",
        l.label, l.instances, l.images, l.res_x, l.res_y, l.units, l.radiance_unit, l.load_ms, l.precompute_ms,
        static_cast<double>(l.device_bytes) / 1048576.0);
  out += fmt::format("memory: {:.1f} MiB in {} buffers\n", static_cast<double>(bytes) / 1048576.0, s.memory.size());
  return out;
}

}  // namespace nf::render
