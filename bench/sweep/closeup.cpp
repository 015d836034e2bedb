#include "bench/sweep/closeup.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "bench/sweep/hash.h"
#include "bench/sweep/plan.h"
#include "core/timer.h"
#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "luminaire/io.h"
#include "luminaire/precompute.h"

namespace nf::bench {

CloseupGeometry closeup_geometry(const lum::Luminaire& l) {
  CloseupGeometry g;
  // Two delta in front of S: near enough that the boxes B_m(p) span many pixels and the light
  // field's position dependence shows (the paper's close-ups), far enough for the beam to form.
  g.distance = 2.0 * l.delta;
  // +-40 degrees around the axis plus the half width of the image rectangle.
  const double half_image = 0.5 * std::max(l.image.size.x, l.image.size.y);
  g.half_size = g.distance * std::tan(40.0 * 3.14159265358979 / 180.0) + 0.5 * half_image;
  return g;
}

std::vector<NfSurface> closeup_surfaces(const CloseupGeometry& g, int res) {
  std::vector<NfSurface> s(static_cast<std::size_t>(res) * res);
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x) {
      NfSurface& q = s[static_cast<std::size_t>(y) * res + x];
      const double fx = (x + 0.5) / res, fy = (y + 0.5) / res;
      q.px = static_cast<float>(g.half_size * (1.0 - 2.0 * fx));
      q.py = static_cast<float>(g.half_size * (1.0 - 2.0 * fy));
      q.pz = static_cast<float>(g.distance);
      q.valid = 1;
      q.nx = 0.0f, q.ny = 0.0f, q.nz = -1.0f;
      q.brdf = NF_BRDF_LAMBERT;
      q.vx = 0.0f, q.vy = 0.0f, q.vz = -1.0f;
      q.roughness = 1.0f;
      q.base_r = q.base_g = q.base_b = 0.8f;
      q.metallic = 0.0f;
    }
  return s;
}

BoxStats box_stats(const lum::Luminaire& l, const CloseupGeometry& g, int grid) {
  std::vector<glm::dvec3> points;
  for (const auto& q : closeup_surfaces(g, grid)) points.emplace_back(q.px, q.py, q.pz);
  return lum::box_stats(l, points);
}

std::string luminaire_fingerprint(const lum::Luminaire& l) {
  Fnv64 h;
  h.add(fmt::format("{} delta={} rec={} basis={} {}x{} o=({},{}) h=({},{}) img=({},{}) ({},{}) {}x{} c={}", l.name,
                    l.delta, static_cast<int>(l.reconstruction), static_cast<int>(l.basis.kind), l.basis.count[0],
                    l.basis.count[1], l.basis.origin.x, l.basis.origin.y, l.basis.cell.x, l.basis.cell.y,
                    l.image.origin.x, l.image.origin.y, l.image.size.x, l.image.size.y, l.image.resolution[0],
                    l.image.resolution[1], l.channels));
  for (const auto& im : l.images) h.add(im.data(), im.size() * sizeof(float));
  return h.hex();
}

CloseupTarget::CloseupTarget(cl::Runtime& rt, const std::string& preset, int res, double resolution_scale)
    : rt_(rt), preset_(closeup_label(preset)), res_(res), scale_(resolution_scale) {
  if (preset_ != preset) {
    // A luminaire manifest (e.g. `nearfield luminaire import` output), used as it is.
    from_file_ = true;
    scale_ = 1.0;
    lum_ = lum::read_luminaire(preset);
  } else {
    lum::GenOptions go;
    go.resolution_scale = resolution_scale;
    lum_ = lum::generate_preset(preset, go);
  }
  pc_ = lum::precompute(lum_);
  fingerprint_ = luminaire_fingerprint(lum_);
  geom_ = closeup_geometry(lum_);
  device_ = std::make_unique<render::DeviceLuminaire>(rt_, pc_);
  sampler_ = std::make_unique<render::Sampler>(rt_);
  const auto surf = closeup_surfaces(geom_, res_);
  surfaces_ = render::upload_surfaces(rt_, surf);
  count_ = static_cast<int>(surf.size());
}

CloseupTarget::~CloseupTarget() = default;

std::string CloseupTarget::describe() const {
  return fmt::format("closeup {}={} scale={} luminaire={} res={} wall z={:.6f} half={:.6f} lambert 0.8",
                     from_file_ ? "file" : "preset", preset_, scale_, fingerprint_, res_, geom_.distance,
                     geom_.half_size);
}

Rendering CloseupTarget::render(const render::SamplingSettings& settings, int frames,
                                const std::function<void()>& on_frame) {
  Rendering out;
  out.frames = frames;
  out.image = Image(res_, res_, 3);
  if (frames >= 2) out.even = Image(res_, res_, 3);
  out.valid.assign(static_cast<std::size_t>(count_), 1);
  std::vector<double> sum(static_cast<std::size_t>(count_) * 3, 0.0), even(frames >= 2 ? sum.size() : 0, 0.0);
  render::LightInstance li;
  li.luminaire = device_.get();
  Timer wall;
  for (int f = 0; f < frames; ++f) {
    render::SamplingSettings s = settings;
    s.frame = settings.frame + static_cast<std::uint32_t>(f);
    const render::FrameStats st = sampler_->run(surfaces_, count_, {&li, 1}, s);
    out.ms.step1 += st.step1_ms;
    out.ms.step2 += st.step2_ms;
    out.ms.cl_other += std::max(0.0, st.wall_ms - st.step1_ms - st.step2_ms);
    Timer t;
    const auto rgb = sampler_->read_radiance();
    for (int i = 0; i < count_; ++i)
      for (int c = 0; c < 3; ++c) sum[static_cast<std::size_t>(i) * 3 + c] += rgb[i][c];
    if (f % 2 == 0 && !even.empty())
      for (int i = 0; i < count_; ++i)
        for (int c = 0; c < 3; ++c) even[static_cast<std::size_t>(i) * 3 + c] += rgb[i][c];
    out.ms.accumulate += t.ms();
    out.samples += sampler_->total_samples();  // K(p) readback: not timed
    if (on_frame) on_frame();
  }
  out.ms.wall = wall.ms();
  const double inv = 1.0 / frames, inv_even = 1.0 / ((frames + 1) / 2);
  for (std::size_t i = 0; i < sum.size(); ++i) out.image.pixels[i] = static_cast<float>(sum[i] * inv);
  for (std::size_t i = 0; i < even.size(); ++i) out.even.pixels[i] = static_cast<float>(even[i] * inv_even);
  return out;
}

}  // namespace nf::bench
