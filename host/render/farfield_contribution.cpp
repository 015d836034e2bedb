#include "render/farfield_contribution.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "cl/buffers.h"
#include "core/error.h"
#include "core/timer.h"
#include "gl/gbuffer.h"
#include "gl/scene_gpu.h"
#include "gl/shadow_maps.h"
#include "render/kurt_table.h"

namespace nf::render {

static_assert(sizeof(NfFarfieldLight) == 96 && offsetof(NfFarfieldLight, nc) == 28 &&
                  offsetof(NfFarfieldLight, cd_offset) == 68 && offsetof(NfFarfieldLight, cr) == 80,
              "NfFarfieldLight must match kernels/shared/farfield.h");

FarfieldContribution::FarfieldContribution(cl::Runtime& rt, const std::vector<scene::FarfieldLightRef>& lights,
                                           const std::vector<scene::Material>& materials)
    : rt_(rt) {
  std::vector<float> angles, cd;
  for (const auto& l : lights) {
    if (!l.table) fail(fmt::format("far-field light '{}': no intensity table", l.name));
    const lum::Goniometric& g = *l.table;
    NfFarfieldLight d{};
    const glm::dvec3 pos(l.to_world[3]);
    d.px = static_cast<float>(pos.x);
    d.py = static_cast<float>(pos.y);
    d.pz = static_cast<float>(pos.z);
    d.scale = static_cast<float>(l.intensity);
    d.cr = static_cast<float>(l.colour.r), d.cg = static_cast<float>(l.colour.g), d.cb = static_cast<float>(l.colour.b);
    // world -> local rotation: the transpose of the rigid transform's rotation (columns = local axes)
    const glm::dvec3 ax(l.to_world[0]), ay(l.to_world[1]), az(l.to_world[2]);
    d.r0x = static_cast<float>(ax.x), d.r0y = static_cast<float>(ax.y), d.r0z = static_cast<float>(ax.z);
    d.r1x = static_cast<float>(ay.x), d.r1y = static_cast<float>(ay.y), d.r1z = static_cast<float>(ay.z);
    d.r2x = static_cast<float>(az.x), d.r2y = static_cast<float>(az.y), d.r2z = static_cast<float>(az.z);
    d.nc = static_cast<nf_int>(g.c.size());
    d.ng = static_cast<nf_int>(g.gamma.size());
    d.c_offset = static_cast<nf_int>(angles.size());
    for (double a : g.c) angles.push_back(static_cast<float>(a));
    d.g_offset = static_cast<nf_int>(angles.size());
    for (double a : g.gamma) angles.push_back(static_cast<float>(a));
    d.cd_offset = static_cast<nf_int>(cd.size());
    // I x intensity <= 1e30 cd x 1e6 (lum::kMaxCandela, scene::kMaxIntensity): finite in float
    for (double v : g.cd) cd.push_back(static_cast<float>(v * l.intensity));
    if (cd.size() > static_cast<std::size_t>(std::numeric_limits<nf_int>::max()))
      fail("far-field lights: the intensity tables hold more than 2^31 values");
    lights_.push_back(d);
    to_world_.push_back(l.to_world);
  }
  lights_buf_ = cl::upload(rt_, lights_, "uploading the far-field lights");
  angles_ = cl::upload(rt_, angles, "uploading the far-field lights' angles");
  cd_ = cl::upload(rt_, cd, "uploading the far-field lights' intensity tables");
  table_bytes_ = table_bytes(lights);
  set_materials(materials);
  // Without shadow maps the kernel takes this one-word buffer and never reads it (OpenCL has no empty buffers).
  vis_ = cl::upload(rt_, std::vector<std::uint32_t>{}, "far-field visibility (unused without shadow maps)");
}

FarfieldContribution::~FarfieldContribution() = default;

void FarfieldContribution::set_materials(const std::vector<scene::Material>& materials) {
  const std::vector<NfKurtMaterial> table = kurt_table(materials);
  kurt_ = cl::upload(rt_, table, "uploading the far-field lights' kurt material table");
  kurt_count_ = static_cast<int>(table.size());
}

// The shadow maps of a far-field light: a cube of six gl::ShadowMaps around the light (the light
// emits over its whole sphere, docs/photometry.md), each with one cell whose reference light is
// the light itself (local origin), looking along one of the local axes +-x, +-y, +-z with a
// symmetric frustum of 45 degrees per side widened to tan = kCubeTan, so that neighbouring faces
// overlap by a few texels and no direction falls between them. A point is lit when every face
// says so: a face that does not see the point counts it as lit (gl/shadow_maps.h), and the face
// (or two, at an edge) that sees it decides. Issue 28: one 75-degree map along +z left everything
// beyond 75 degrees lit, so a light inside a closed box lit the floor outside it.
namespace {

constexpr double kCubeTan = 1.05;

// Rotations taking local +z onto the six face axes (+z, -z, +x, -x, +y, -y).
std::vector<glm::dmat4> cube_faces() {
  const double half = 0.5 * 3.14159265358979323846;
  const glm::dmat4 id(1.0);
  return {id,
          glm::rotate(id, 2.0 * half, glm::dvec3(0, 1, 0)),
          glm::rotate(id, half, glm::dvec3(0, 1, 0)),
          glm::rotate(id, -half, glm::dvec3(0, 1, 0)),
          glm::rotate(id, -half, glm::dvec3(1, 0, 0)),
          glm::rotate(id, half, glm::dvec3(1, 0, 0))};
}

}  // namespace

void FarfieldContribution::update_visibility(const FrameInputs& in, ContributionFrame& f) {
  const bool wanted = in.settings.visibility == Visibility::shadowmaps && in.scene_gpu && in.gbuffer && in.geometry &&
                      in.geometry->can_occlude();
  vis_used_ = wanted;
  if (!wanted) return;
  const std::size_t faces = cube_faces().size();
  if (maps_.empty() || map_size_ != in.settings.shadow_map_size) {
    Timer t;
    maps_.clear();
    map_size_ = in.settings.shadow_map_size;
    for (const auto& m : to_world_)
      for (const auto& face : cube_faces()) {
        gl::ShadowMapSpec spec;
        spec.lights = {glm::dvec3(0.0)};
        spec.cells_x = spec.cells_y = 1;
        spec.to_world = m * face;
        spec.size = map_size_;
        spec.frustum = gl::ShadowFrustum{-kCubeTan, kCubeTan, -kCubeTan, kCubeTan, 0.005};
        maps_.push_back(std::make_unique<gl::ShadowMaps>(spec));
        maps_.back()->render(*in.scene_gpu);
      }
    f.parts_ms.emplace_back("shadow maps", t.ms());
    f.step1_ms += t.ms();
    vis_valid_ = false;
  }
  if (vis_valid_ && in.view_version != 0 && in.view_version == vis_version_) return;
  Timer t;
  const std::size_t n = static_cast<std::size_t>(std::max(in.count, 0)), nl = to_world_.size();
  std::vector<std::uint32_t> bits(visibility_bytes(n, nl) / sizeof(std::uint32_t), 0u);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = 0; k < nl; ++k) bits[p * nl + k] = 1u;
  for (std::size_t m = 0; m < maps_.size(); ++m) {
    const std::size_t k = m / faces;
    const std::vector<std::uint32_t> v = maps_[m]->visibility(*in.gbuffer);  // one word per pixel
    if (v.size() != n) fail(fmt::format("far-field shadow map {}: {} visibility words for {} pixels", m, v.size(), n));
    for (std::size_t p = 0; p < n; ++p) bits[p * nl + k] &= v[p] & 1u;
  }
  vis_ = cl::upload(rt_, bits, "uploading the far-field visibility");
  vis_bytes_ = visibility_bytes(n, nl);
  vis_version_ = in.view_version;
  vis_valid_ = true;
  f.parts_ms.emplace_back("visibility", t.ms());
  f.step1_ms += t.ms();
}

void FarfieldContribution::prepare(const FrameInputs&) {
  if (!shade_) shade_ = FarfieldShadeKernel(rt_, "farfield.cl", "farfield_shade");
  if (!shade_picks_) shade_picks_ = FarfieldPicksKernel(rt_, "farfield.cl", "farfield_shade_picks");
}

// One launch of farfield_shade over every surface (kernels/farfield.cl has the formula), or with
// light selection (FrameInputs::picks) of farfield_shade_picks: only the picked lights, weighted.
ContributionFrame FarfieldContribution::add(const FrameInputs& in, std::vector<glm::vec4>& radiance) {
  prepare(in);
  ContributionFrame f;
  update_visibility(in, f);
  Timer wall;
  const std::size_t n = static_cast<std::size_t>(std::max(in.count, 1));
  if (out_bytes_ != output_bytes(n)) {
    cl::call([&] { out_ = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, output_bytes(n)); },
             "far-field output buffer");
    out_bytes_ = output_bytes(n);
  }
  const Sampler::Picks* picks = in.picks;
  if (picks && (picks->farfield != static_cast<int>(lights_.size()) || picks->count != in.count))
    fail(
        fmt::format("far-field lights: the light selection has {} far-field lights for {} surfaces, expected {} for {}",
                    picks->farfield, picks->count, lights_.size(), in.count));
  ::cl::Event ev;
  if (picks) {
    shade_picks_.bind(in.surfaces, in.count, lights_buf_, static_cast<cl_int>(lights_.size()), angles_, cd_, kurt_,
                      kurt_count_, vis_, vis_used_ ? 1 : 0, *picks->sel, *picks->w, picks->picks, picks->first_farfield,
                      out_);
    ev = rt_.launch(shade_picks_.get(), ::cl::NDRange(n));
  } else {
    shade_.bind(in.surfaces, in.count, lights_buf_, static_cast<cl_int>(lights_.size()), angles_, cd_, kurt_,
                kurt_count_, vis_, vis_used_ ? 1 : 0, out_);
    ev = rt_.launch(shade_.get(), ::cl::NDRange(n));
  }
  cl::call([&] { ev.wait(); }, "far-field kernel");
  f.step2_ms = cl::Runtime::event_ms(ev);
  f.wall_ms = wall.ms();
  Timer readback;
  add_radiance(radiance, read_radiance(rt_, out_, in.count, "reading the far-field radiance"));
  // lights evaluated: every light at every surface, or (selection) at most M per surface
  f.samples = static_cast<std::uint64_t>(std::max(in.count, 0)) *
              (picks ? std::min<std::size_t>(static_cast<std::size_t>(picks->picks), lights_.size()) : lights_.size());
  f.readback_ms = readback.ms();
  return f;
}

std::size_t FarfieldContribution::device_bytes() const {
  return table_bytes_ + out_bytes_ + vis_bytes_ + kurt_table_bytes(static_cast<std::size_t>(kurt_count_));
}

std::size_t FarfieldContribution::table_bytes(const std::vector<scene::FarfieldLightRef>& lights) {
  std::size_t values = 0;  // C angles, gamma angles and the nc x ng intensities of each table
  for (const auto& l : lights)
    if (l.table) values += l.table->c.size() + l.table->gamma.size() + l.table->cd.size();
  return lights.size() * sizeof(NfFarfieldLight) + values * sizeof(float);
}

std::size_t FarfieldContribution::output_bytes(std::size_t pixels) {
  return std::max<std::size_t>(pixels, 1) * sizeof(cl_float4);
}

std::size_t FarfieldContribution::visibility_bytes(std::size_t pixels, std::size_t lights) {
  return std::max<std::size_t>(pixels * lights, 1) * sizeof(std::uint32_t);
}

std::size_t FarfieldContribution::estimate_bytes(const std::vector<scene::FarfieldLightRef>& lights, std::size_t pixels,
                                                 bool shadow_maps, std::size_t kurt_entries) {
  return table_bytes(lights) + output_bytes(pixels) + (shadow_maps ? visibility_bytes(pixels, lights.size()) : 0) +
         kurt_table_bytes(kurt_entries);
}

}  // namespace nf::render
