#include "reference/integrator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/excerpt.h"
#include "core/progress.h"
#include "core/timer.h"
#include "luminaire/parallel.h"
#include "reference/brdf.h"
#include "reference/farfield_light.h"
#include "reference/ray_scene.h"
#include "reference/rng.h"
#include "reference/surface_point.h"

namespace nf::ref {

std::string to_string(Only o) {
  switch (o) {
    case Only::luminaires:
      return "luminaires";
    case Only::environment:
      return "environment";
    case Only::indirect:
      return "indirect";
    default:
      return "all";
  }
}

Only parse_only(const std::string& s, const std::string& what) {
  for (Only o : {Only::all, Only::luminaires, Only::environment, Only::indirect})
    if (to_string(o) == s) return o;
  fail(fmt::format("{}: unknown value '{}' (known: all | luminaires | environment | indirect)", what, excerpt(s)));
}

void ReferenceSettings::validate(bool has_environment) const {
  if (spp < 1 || spp > (1 << 24)) fail(fmt::format("--spp must be in 1..{}, got {}", 1 << 24, spp));
  if (bounces != 0 && bounces != 1) fail(fmt::format("--bounces must be 0 or 1, got {}", bounces));
  if (only == Only::indirect && bounces != 1) fail("--only indirect needs --bounces 1");
  if (only == Only::environment && !has_environment) fail("--only environment: the scene has no environment");
}

std::vector<std::pair<std::string, std::string>> ReferenceSettings::attributes() const {
  return {{"nearfield:reference_spp", std::to_string(spp)},   {"nearfield:reference_bounces", std::to_string(bounces)},
          {"nearfield:reference_only", to_string(only)},      {"nearfield:reference_seed", std::to_string(seed)},
          {"nearfield:reference_jitter", jitter ? "1" : "0"}, {"nearfield:reference_mis", to_string(mis)}};
}

std::vector<std::uint8_t> ReferenceResult::valid_mask() const {
  std::vector<std::uint8_t> v(kinds.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) v[i] = kinds[i] == 1 ? 1 : 0;
  return v;
}

namespace {

using glm::dvec3;

struct Counters {
  std::uint64_t camera = 0, shadow = 0, bounce = 0, dropped = 0;
};

// One thread's integrator: the scene, the settings and reusable per-point tables.
class Tracer {
 public:
  Tracer(const scene::Scene& s, const RayScene& rays, const std::vector<LightFieldLight>& lights,
         const EnvironmentMap* env, const ReferenceSettings& settings)
      : scene_(s),
        rays_(rays),
        lights_(lights),
        env_(env),
        set_(settings),
        camera_tables_(lights.size()),
        bounce_tables_(lights.size()),
        eps_(2e-5 * rays.scale()) {}

  // One camera sample of pixel (x, y); `kind` receives the pixel class. `reuse`: the previous
  // sample went through the same point (pixel centres): its camera ray, surface point and light
  // tables are reused (the ray would be the same).
  dvec3 sample(int x, int y, Rng& rng, bool reuse, std::uint8_t& kind, Counters& c) {
    if (!reuse) trace_camera(x, y, rng, c);
    kind = view_.kind;
    if (view_.kind != 1) return view_.radiance;
    return shade(view_.sp, view_.v, rng, true, reuse, c);
  }

 private:
  struct CameraView {
    std::uint8_t kind = 0;
    dvec3 radiance{0.0};  // background or luminaire pixels
    SurfacePoint sp;
    dvec3 v{0.0};
  };

  void trace_camera(int x, int y, Rng& rng, Counters& c) {
    const scene::Camera& cam = scene_.camera;
    const double jx = set_.jitter ? rng.next() : 0.5, jy = set_.jitter ? rng.next() : 0.5;
    if (!cam.inside(x + jx, y + jy)) {  // outside a fisheye's 180-degree circle: black, no ray
      view_.kind = 0;
      view_.radiance = dvec3(0.0);
      return;
    }
    const scene::Camera::Ray ray = cam.ray(x + jx, y + jy);
    // near: a plane for the perspective camera, a sphere for the fisheye (whose rays reach 90
    // degrees and beyond from the view direction).
    const double tmin = cam.projection == scene::Camera::Projection::fisheye
                            ? cam.near
                            : cam.near / std::max(glm::dot(ray.direction, cam.forward()), 1e-6);
    ++c.camera;
    const RayHit hit = rays_.intersect(ray.origin, ray.direction, tmin, std::numeric_limits<double>::infinity());
    double nearest = hit.hit ? hit.t : std::numeric_limits<double>::infinity();
    bool sees_luminaire = false;
    dvec3 lum(0.0);
    for (const auto& light : lights_) {
      dvec3 r(0.0);
      const double t = camera_sees(light, ray.origin, ray.direction, r);
      if (t > 0.0 && t < nearest) nearest = t, lum = r, sees_luminaire = true;
    }
    view_.radiance = dvec3(0.0);
    if (sees_luminaire) {
      view_.kind = 2;
      if (set_.only == Only::all || set_.only == Only::luminaires) view_.radiance = lum;
    } else if (!hit.hit) {
      view_.kind = 0;
      if (env_ && (set_.only == Only::all || set_.only == Only::environment))
        view_.radiance = env_->eval(ray.direction);
    } else {
      view_.kind = 1;
      view_.sp = surface_point(scene_.geometry, rays_, hit, ray.direction);
      view_.v = -ray.direction;
    }
  }

  bool visible(const SurfacePoint& sp, dvec3 w, double dist, Counters& c) const {
    if (!(glm::dot(sp.ng, w) > 0.0)) return false;  // below the geometric surface
    ++c.shadow;
    return !rays_.occluded(sp.p + sp.ng * eps_, w, 0.0, dist - eps_);
  }

  // `tables`: the camera point's (reused across a pixel's samples when `reuse`) or the bounce's.
  dvec3 luminaires(const SurfacePoint& sp, dvec3 v, Rng& rng, std::vector<LightTable>& tables, bool reuse,
                   Counters& c) {
    dvec3 sum(0.0);
    for (std::size_t i = 0; i < lights_.size(); ++i) {
      if (!reuse) build_table(lights_[i], sp.p, tables[i]);
      const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
      const LightSample ls = sample_light(lights_[i], tables[i], u0, u1, u2);
      if (!ls.valid) continue;
      const dvec3 f = brdf_eval(sp.material, sp.ns, v, ls.direction);
      const double cos = glm::dot(sp.ns, ls.direction);
      if (!(cos > 0.0) || f == dvec3(0.0)) continue;
      // MIS (reference/luminaire_mis.h): w_L = h(q_m, p_B) for the pair (m, w) this sample drew.
      const double w = set_.mis == MisHeuristic::none
                           ? 1.0
                           : mis_weight(set_.mis, ls.pdf, brdf_pdf(sp.material, sp.ns, v, ls.direction));
      if (!(w > 0.0)) continue;
      if (visible(sp, ls.direction, ls.distance, c)) sum += ls.weight * f * (cos * w);
    }
    // Far-field point lights (reference/farfield_light.h): one deterministic shadow ray each.
    for (const auto& l : scene_.farfield_lights) {
      const FarfieldSample s = farfield_sample(*l.table, l.to_world, l.intensity, sp.p);
      if (!s.valid || !(s.intensity > 0.0)) continue;
      const double cos = glm::dot(sp.ns, s.w);
      if (!(cos > 0.0)) continue;
      const dvec3 f = brdf_eval(sp.material, sp.ns, v, s.w);
      if (f == dvec3(0.0)) continue;
      if (visible(sp, s.w, s.distance, c)) sum += f * l.colour * (s.intensity * cos / (s.distance * s.distance));
    }
    return sum;
  }

  // The BRDF sample's share of the luminaires (MIS, reference/luminaire_mis.h): for every instance
  // and image m whose term the direction meets, w_B = h(p_B, q_m) times intensity x C_m Psi_m
  // (what a camera ray sees), if no surface is nearer than the sampler's shadow-ray target (the
  // same visibility as the light samples: hit.t vs distance - eps). Times f_r cos / p_B by the caller.
  dvec3 luminaires_hit(const BrdfSample& bs, const RayHit& hit, const std::vector<LightTable>& tables) {
    dvec3 sum(0.0);
    for (std::size_t i = 0; i < lights_.size(); ++i) {
      if (!light_hit(lights_[i], tables[i], bs.l, hit_)) continue;
      if (hit.hit && hit.t < hit_.distance - eps_) continue;
      for (std::size_t k = 0; k < hit_.images.size(); ++k)
        sum += hit_.radiance[k] * mis_weight(set_.mis, bs.pdf, hit_.pdf[k]);
    }
    return sum;
  }

  // Environment by MIS (power heuristic): the map sample here, the BRDF sample in shade().
  dvec3 environment_sample(const SurfacePoint& sp, dvec3 v, Rng& rng, Counters& c) {
    const double u0 = rng.next(), u1 = rng.next();
    const EnvironmentMap::Sample es = env_->sample(u0, u1);
    if (!(es.pdf > 0.0)) return dvec3(0.0);
    const double cos = glm::dot(sp.ns, es.direction);
    if (!(cos > 0.0)) return dvec3(0.0);
    const dvec3 f = brdf_eval(sp.material, sp.ns, v, es.direction);
    if (f == dvec3(0.0) || !visible(sp, es.direction, std::numeric_limits<double>::infinity(), c)) return dvec3(0.0);
    const double pb = brdf_pdf(sp.material, sp.ns, v, es.direction);
    const double w = es.pdf * es.pdf / (es.pdf * es.pdf + pb * pb);
    return env_->eval(es.direction) * f * (cos * w / es.pdf);
  }

  dvec3 shade(const SurfacePoint& sp, dvec3 v, Rng& rng, bool camera_level, bool reuse, Counters& c) {
    const bool direct_lum = !camera_level || set_.only == Only::all || set_.only == Only::luminaires;
    const bool direct_env = env_ && (!camera_level || set_.only == Only::all || set_.only == Only::environment);
    const bool bounce = camera_level && set_.bounces == 1 && (set_.only == Only::all || set_.only == Only::indirect);
    dvec3 sum(0.0);
    if (direct_lum)
      sum += luminaires(sp, v, rng, camera_level ? camera_tables_ : bounce_tables_, reuse && camera_level, c);
    if (direct_env) sum += environment_sample(sp, v, rng, c);
    // One BRDF sample serves the environment's MIS, the luminaires' MIS and the bounce.
    const bool lum_mis = direct_lum && set_.mis != MisHeuristic::none && !lights_.empty();
    if (!direct_env && !bounce && !lum_mis) return sum;
    const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
    const BrdfSample bs = brdf_sample(sp.material, sp.ns, v, u0, u1, u2);
    if (!(bs.pdf > 0.0) || !(glm::dot(sp.ng, bs.l) > 0.0)) return sum;
    const dvec3 f = brdf_eval(sp.material, sp.ns, v, bs.l) * (glm::dot(sp.ns, bs.l) / bs.pdf);
    if (f == dvec3(0.0)) return sum;
    ++c.bounce;
    const RayHit hit = rays_.intersect(sp.p + sp.ng * eps_, bs.l, 0.0, std::numeric_limits<double>::infinity());
    if (lum_mis) sum += f * luminaires_hit(bs, hit, camera_level ? camera_tables_ : bounce_tables_);
    if (!hit.hit) {
      if (direct_env) {
        const double pe = env_->pdf(bs.l);
        sum += env_->eval(bs.l) * f * (bs.pdf * bs.pdf / (bs.pdf * bs.pdf + pe * pe));
      }
      return sum;
    }
    if (bounce) {
      const SurfacePoint y = surface_point(scene_.geometry, rays_, hit, bs.l);
      sum += f * shade(y, -bs.l, rng, false, false, c);
    }
    return sum;
  }

  const scene::Scene& scene_;
  const RayScene& rays_;
  const std::vector<LightFieldLight>& lights_;
  const EnvironmentMap* env_;
  const ReferenceSettings& set_;
  std::vector<LightTable> camera_tables_, bounce_tables_;
  LightHit hit_;  // reused by luminaires_hit
  CameraView view_;
  double eps_;
};

}  // namespace

void ImageRegion::validate(int image_width, int image_height, int spp) const {
  if (width < 1 || height < 1 || x < 0 || y < 0 || x + width > image_width || y + height > image_height)
    fail(fmt::format("--tile {},{},{},{} is not a non-empty rectangle inside the {}x{} image", x, y, width, height,
                     image_width, image_height));
  if (first_sample < 0 || sample_count < 1 || first_sample + sample_count > spp)
    fail(fmt::format("--samples {},{} is not a non-empty range inside 0..{} (--spp)", first_sample, sample_count, spp));
}

void finish_pixel(const SampleSums& root, int spp, float rgb[3], float& variance) {
  const auto n = static_cast<double>(spp);
  for (int k = 0; k < 3; ++k) rgb[k] = static_cast<float>(root[k] / n);
  const double my = root[3] / n;
  variance = spp > 1 ? static_cast<float>(std::max(0.0, (root[4] / n - my * my) / (n - 1.0))) : 0.0f;
}

namespace {

// One pixel's samples of the region's range: one sum per node (sample_nodes), leaves summed
// pairwise (reference/sample_sums.h). Returns the kind seen by the range's first sample.
std::uint8_t pixel_sums(Tracer& tracer, const ReferenceSettings& settings, const ImageRegion& r,
                        const std::vector<SampleNode>& nodes, int x, int y, int image_width, double* out, Counters& c) {
  const std::uint64_t pixel =
      static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(image_width) + static_cast<std::uint64_t>(x);
  std::uint8_t kind = 0;
  PairwiseSums acc;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    acc.clear();
    for (std::int64_t s = nodes[n].first; s < nodes[n].end; ++s) {
      Rng rng(settings.seed, pixel, static_cast<std::uint64_t>(s));
      std::uint8_t k = 0;
      // Without jitter every sample sees the same point: its camera ray and light tables are
      // computed once per pixel (the values are the same as if they were computed again).
      dvec3 L = tracer.sample(x, y, rng, !settings.jitter && s > r.first_sample, k, c);
      if (s == r.first_sample) kind = k;
      if (!std::isfinite(L.x + L.y + L.z)) {
        L = dvec3(0.0);
        ++c.dropped;
      }
      const double yl = 0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z;
      acc.push(0, {L.x, L.y, L.z, yl, yl * yl});
    }
    const SampleSums v = acc.result();
    std::copy(v.begin(), v.end(), out + n * kSumChannels);
  }
  return kind;
}

}  // namespace

ReferencePart render_reference_part(const scene::Scene& scene, const std::vector<LightFieldLight>& lights,
                                    const EnvironmentMap* environment, const ReferenceSettings& settings,
                                    const ImageRegion& region) {
  settings.validate(environment != nullptr);
  const int w = scene.camera.width, h = scene.camera.height;
  region.validate(w, h, settings.spp);
  ReferencePart out;
  out.region = region;
  out.nodes = sample_nodes(region.first_sample, region.sample_count, settings.spp);
  const std::size_t pixels = static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height);
  const std::size_t stride = out.nodes.size() * kSumChannels;
  out.sums.assign(pixels * stride, 0.0);
  out.kinds.assign(pixels, 0);
  Timer build;
  const RayScene rays(scene.geometry);
  out.stats.build_ms = build.ms();
  out.stats.triangles = rays.triangle_count();
  out.stats.threads = lum::resolve_threads(settings.threads);
  Timer timer;
  std::unique_ptr<Progress> progress;
  if (settings.progress) progress = std::make_unique<Progress>("reference", static_cast<std::size_t>(region.height));
  std::mutex mutex;
  Counters total;
  lum::parallel_for(region.height, settings.threads, [&](int row) {
    Tracer tracer(scene, rays, lights, environment, settings);
    Counters c;
    for (int col = 0; col < region.width; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * region.width + col;
      out.kinds[i] = pixel_sums(tracer, settings, region, out.nodes, region.x + col, region.y + row, w,
                                out.sums.data() + i * stride, c);
    }
    std::lock_guard lock(mutex);
    total.camera += c.camera;
    total.shadow += c.shadow;
    total.bounce += c.bounce;
    total.dropped += c.dropped;
    if (progress) progress->advance();
  });
  if (progress) progress->finish();
  out.stats.render_ms = timer.ms();
  out.stats.camera_rays = total.camera;
  out.stats.shadow_rays = total.shadow;
  out.stats.bounce_rays = total.bounce;
  out.stats.dropped = total.dropped;
  out.stats.samples = static_cast<std::uint64_t>(pixels) * static_cast<std::uint64_t>(region.sample_count);
  return out;
}

ReferenceResult render_reference(const scene::Scene& scene, const std::vector<LightFieldLight>& lights,
                                 const EnvironmentMap* environment, const ReferenceSettings& settings) {
  const int w = scene.camera.width, h = scene.camera.height;
  ReferencePart part =
      render_reference_part(scene, lights, environment, settings, ImageRegion::whole(w, h, settings.spp));
  ReferenceResult out;
  out.image = Image(w, h, 3);
  out.variance = Image(w, h, 1);
  out.kinds = std::move(part.kinds);
  out.stats = part.stats;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      SampleSums root;
      std::copy_n(part.sums.data() + i * kSumChannels, kSumChannels, root.begin());
      float rgb[3];
      finish_pixel(root, settings.spp, rgb, out.variance.at(x, y, 0));
      for (int k = 0; k < 3; ++k) out.image.at(x, y, k) = rgb[k];
    }
  return out;
}

}  // namespace nf::ref
