#include "app/calculation_eval.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "app/command.h"
#include "cl/runtime.h"
#include "core/error.h"
#include "core/log.h"
#include "core/timer.h"
#include "gl/context.h"
#include "gl/scene_gpu.h"
#include "gl/shadow_maps.h"
#include "reference/farfield_light.h"
#include "reference/light_field_light.h"
#include "reference/ray_scene.h"
#include "reference/rng.h"
#include "render/cl_shadow_visibility.h"
#include "render/device_luminaire.h"
#include "render/luminaire_cache.h"
#include "render/probe.h"
#include "render/reference_lights.h"
#include "render/sampler.h"

namespace nf::app {
namespace {

double luminance_y(const glm::dvec3& v) { return 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z; }  // Rec. 709 Y

// Runs f(i) for i in [0, n) on the hardware threads.
template <typename F>
void parallel_for(std::size_t n, F&& f) {
  const unsigned t = std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), static_cast<unsigned>(n)));
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < t; ++k)
    pool.emplace_back([&, k] {
      for (std::size_t i = k; i < n; i += t) f(i);
    });
  for (auto& th : pool) th.join();
}

// Far-field lights, closed form with one exact shadow ray per point and light:
//   E = I(C, gamma) max(0, n.w) / r^2 (Y; the light's colour has luminance 1).
std::vector<double> farfield_part(const scene::Scene& scene, const ref::RayScene& rays,
                                  const std::vector<scene::CalculationPoint>& pts) {
  std::vector<double> e(pts.size(), 0.0);
  const double eps = 2e-5 * rays.scale();
  parallel_for(pts.size(), [&](std::size_t i) {
    const auto& q = pts[i];
    for (const auto& l : scene.farfield_lights) {
      const ref::FarfieldSample s = ref::farfield_sample(*l.table, l.to_world, l.intensity, q.p);
      if (!s.valid || !(s.intensity > 0.0)) continue;
      const double cos = glm::dot(q.n, s.w);
      if (!(cos > 0.0)) continue;
      if (rays.occluded(q.p + q.n * eps, s.w, 0.0, s.distance - eps)) continue;
      e[i] += luminance_y(l.colour) * s.intensity * cos / (s.distance * s.distance);
    }
  });
  return e;
}

// One batch of light-field light through the OpenCL kernels with the frame's shadow maps.
class KernelLightFields {
 public:
  KernelLightFields(const scene::Scene& scene, render::LuminaireSet& set,
                    const std::vector<scene::CalculationPoint>& pts, const CalcOptions& o, std::string& visibility)
      : rt_(global_options().cl_device), sampler_(rt_) {
    for (const auto& src : set.sources)
      devices_.push_back(std::make_unique<render::DeviceLuminaire>(rt_, src.precomputed));
    std::vector<NfSurface> surfaces;
    for (const auto& q : pts) surfaces.push_back(render::probe_surface(q.p.x, q.p.y, q.p.z, q.n.x, q.n.y, q.n.z));
    surfaces_ = render::upload_surfaces(rt_, surfaces);
    count_ = static_cast<int>(surfaces.size());
    const bool maps = scene.needs_shadow_maps();
    vis_.resize(scene.luminaires.size());
    vis_bytes_.resize(scene.luminaires.size(), 0);
    std::vector<int> words(scene.luminaires.size(), 0);
    if (maps) {
      Timer timer;
      context_ = gl::create_headless_context();
      context_->make_current();
      gl::SceneGpu gpu(scene.geometry);
      for (std::size_t i = 0; i < scene.luminaires.size(); ++i) {
        const lum::Precomputed& pc = set.sources[set.source_of[i]].precomputed;
        gl::ShadowMaps sm(gl::make_shadow_map_spec(pc.params, pc.ref_lights, scene.luminaires[i].to_world,
                                                   scene.render.shadow_map_size));
        sm.render(gpu);
        render::ClShadowVisibility cv(rt_);
        cv.upload(sm);
        cv.run(surfaces_, count_, 0, sm, vis_[i], vis_bytes_[i]);  // calculation points: no image
        words[i] = sm.words_per_pixel();
      }
      visibility = fmt::format(
          "light fields: the frame's shadow maps ({} x {} per cell, tested per point by "
          "kernels/shadow_visibility.cl; {:.1f} s)",
          scene.render.shadow_map_size, scene.render.shadow_map_size, timer.ms() * 1e-3);
    } else {
      visibility =
          nf::scene::choice_value<nf::scene::Visibility>(scene.render.visibility) == nf::scene::Visibility::none
              ? "light fields: none (the scene's render.visibility is none)"
              : "light fields: none needed (nothing in the scene can occlude)";
    }
    for (std::size_t i = 0; i < scene.luminaires.size(); ++i) {
      render::LightInstance li;
      li.luminaire = devices_[set.source_of[i]].get();
      li.instance = render::make_instance(glm::inverse(scene.luminaires[i].to_world), scene.luminaires[i].intensity);
      if (maps) {
        li.visibility = &vis_[i];
        li.vis_words = words[i];
      }
      lights_.push_back(li);
    }
    settings_ = render::ProbeSettings{}.sampling;
    settings_.method = render::parse_method(o.method, "--method");
    settings_.spp = o.spp;
    settings_.seed = o.seed;
    settings_.validate();
  }
  std::vector<double> batch(int b) {
    render::SamplingSettings s = settings_;
    s.frame = static_cast<std::uint32_t>(b);
    sampler_.run(surfaces_, count_, lights_, s, 1);  // fixed surfaces: the pixel cache keeps A_m(p)
    const auto rgb = sampler_.read_radiance();
    std::vector<double> y(rgb.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = luminance_y(glm::dvec3(rgb[i].x, rgb[i].y, rgb[i].z));
    return y;
  }

 private:
  std::unique_ptr<gl::Context> context_;
  cl::Runtime rt_;
  render::Sampler sampler_;
  std::vector<std::unique_ptr<render::DeviceLuminaire>> devices_;
  ::cl::Buffer surfaces_;
  int count_ = 0;
  std::vector<::cl::Buffer> vis_;
  std::vector<std::size_t> vis_bytes_;
  std::vector<render::LightInstance> lights_;
  render::SamplingSettings settings_;
};

// One batch of light-field light by the reference estimator (reference/light_field_light.h): per
// point and instance K samples, each with an exact shadow ray; sample k of batch b of point i uses
// Rng(seed, i, b K + k), so batches are independent and reproducible.
class ReferenceLightFields {
 public:
  ReferenceLightFields(const scene::Scene& scene, const render::LuminaireSet& set, const ref::RayScene& rays,
                       const std::vector<scene::CalculationPoint>& pts, const CalcOptions& o)
      : lights_(render::reference_lights(scene, set)),
        rays_(rays),
        pts_(pts),
        spp_(o.spp),
        seed_(o.seed),
        eps_(2e-5 * rays.scale()) {
    tables_.resize(pts.size() * lights_.size());
    parallel_for(pts.size(), [&](std::size_t i) {
      for (std::size_t m = 0; m < lights_.size(); ++m)
        ref::build_table(lights_[m], pts_[i].p, tables_[i * lights_.size() + m]);
    });
  }
  std::vector<double> batch(int b) {
    std::vector<double> y(pts_.size(), 0.0);
    parallel_for(pts_.size(), [&](std::size_t i) {
      const auto& q = pts_[i];
      ref::Rng rng(seed_, i, static_cast<std::uint64_t>(b) * static_cast<std::uint64_t>(spp_));
      double sum = 0.0;
      for (int k = 0; k < spp_; ++k)
        for (std::size_t m = 0; m < lights_.size(); ++m) {
          const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
          const ref::LightSample ls = ref::sample_light(lights_[m], tables_[i * lights_.size() + m], u0, u1, u2);
          if (!ls.valid) continue;
          const double cos = glm::dot(q.n, ls.direction);
          if (!(cos > 0.0)) continue;
          if (rays_.occluded(q.p + q.n * eps_, ls.direction, 0.0, ls.distance - eps_)) continue;
          sum += luminance_y(ls.weight) * cos;
        }
      y[i] = sum / spp_;
    });
    return y;
  }

 private:
  std::vector<ref::LightFieldLight> lights_;
  const ref::RayScene& rays_;
  const std::vector<scene::CalculationPoint>& pts_;
  int spp_;
  std::uint32_t seed_;
  double eps_;
  std::vector<ref::LightTable> tables_;
};

}  // namespace

CalcResult evaluate_calculation_surfaces(const scene::Scene& scene,
                                         const std::vector<scene::CalculationSurface>& surfaces, const CalcOptions& o) {
  Timer timer;
  CalcResult r;
  std::vector<scene::CalculationPoint> pts;
  std::vector<int> group;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    r.layouts.push_back(surfaces[s].layout());
    for (const auto& q : r.layouts.back().points) {
      pts.push_back(q);
      group.push_back(static_cast<int>(s));
    }
  }
  const std::string name = scene.file.empty() ? std::string("<scene>") : scene.file.string();
  const ref::RayScene rays(scene.geometry);
  const std::vector<double> ff = farfield_part(scene, rays, pts);
  std::vector<double> total = ff, se(pts.size(), 0.0);
  std::string lf_vis;
  if (!scene.luminaires.empty() && !pts.empty()) {
    render::LuminaireSet set = render::load_luminaires(scene.luminaires, name);
    std::unique_ptr<KernelLightFields> kernels;
    std::unique_ptr<ReferenceLightFields> reference;
    if (o.reference) {
      reference = std::make_unique<ReferenceLightFields>(scene, set, rays, pts, o);
      lf_vis = "light fields: exact (one Embree shadow ray per sample, the reference renderer's estimator)";
    } else {
      kernels = std::make_unique<KernelLightFields>(scene, set, pts, o, lf_vis);
    }
    const auto batch = [&](int b) {
      std::vector<double> y = o.reference ? reference->batch(b) : kernels->batch(b);
      for (std::size_t i = 0; i < y.size(); ++i) y[i] += ff[i];
      return y;
    };
    if (o.fixed) {
      total = batch(0);
      r.noise = CalcResult::Noise::fixed;
      r.spp = o.spp;
    } else {
      BatchStopRule rule = o.rule;
      rule.group = group;
      r.est = run_batches(pts.size(), rule, batch, [&](const BatchEstimate& e) {
        if (!e.converged && e.batches < rule.max_batches)
          log::info("probe: {} samples per point, worst relative SE {:.3g} %, going on ({:.1f} s)", e.batches * o.spp,
                    100.0 * e.worst_rel, timer.ms() * 1e-3);
      });
      total = r.est.mean;
      se = r.est.se;
      r.noise = CalcResult::Noise::adaptive;
      r.spp = r.est.batches * o.spp;
    }
  }
  r.visibility =
      (lf_vis.empty() ? std::string() : lf_vis + "; ") +
      (scene.farfield_lights.empty() ? std::string("no far-field lights")
                                     : std::string("far-field lights: exact (one Embree shadow ray per point)"));
  std::size_t k = 0;
  for (const auto& l : r.layouts) {
    r.e.emplace_back(total.begin() + static_cast<std::ptrdiff_t>(k),
                     total.begin() + static_cast<std::ptrdiff_t>(k + l.points.size()));
    r.se.emplace_back(se.begin() + static_cast<std::ptrdiff_t>(k),
                      se.begin() + static_cast<std::ptrdiff_t>(k + l.points.size()));
    k += l.points.size();
  }
  r.seconds = timer.ms() * 1e-3;
  return r;
}

}  // namespace nf::app
