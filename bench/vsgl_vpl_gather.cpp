#include "bench/vsgl_vpl_gather.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <thread>

#include <glm/geometric.hpp>

#include "reference/brdf.h"
#include "reference/ray_scene.h"

namespace nf::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

double lum(glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

ref::ShadingMaterial material_of(const NfSurface& s) {
  ref::ShadingMaterial m;
  m.ggx = s.brdf == NF_BRDF_GGX;
  m.base = glm::dvec3(s.base_r, s.base_g, s.base_b);
  m.metallic = s.metallic;
  m.alpha = std::max(static_cast<double>(s.roughness) * s.roughness, 1e-3);
  return m;
}

// The diffuse part of f_r (reference/brdf.h): lambert base / pi; ggx (1 - F(v.h)) (1 - metallic) base / pi.
glm::dvec3 diffuse_part(const ref::ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  if (glm::dot(n, l) <= 0.0) return glm::dvec3(0.0);
  if (!m.ggx) return m.base / kPi;
  const glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), m.base, m.metallic);
  const glm::dvec3 h = glm::normalize(v + l);
  const double q = std::pow(1.0 - std::clamp(glm::dot(v, h), 0.0, 1.0), 5.0);
  const glm::dvec3 f = f0 + (glm::dvec3(1.0) - f0) * q;
  return (glm::dvec3(1.0) - f) * (1.0 - m.metallic) * m.base / kPi;
}

struct Vpl {
  glm::dvec3 y, n, l, phi;
  ref::ShadingMaterial m;
  int block = 0;
};

}  // namespace

VplGather gather_vpls(render::VsglContribution& v, int rsm_size, const std::vector<NfSurface>& pixels, int merge,
                      const scene::Geometry* geometry, int threads) {
  VplGather out;
  std::vector<Vpl> vpls;
  std::vector<glm::dvec3> centre;  // per block: flux-weighted mean position
  std::vector<double> weight;
  const int bs = (rsm_size + merge - 1) / merge;
  for (int i = 0; i < v.instances(); ++i) {
    const auto& rsm = v.rsm_surfaces(i);
    const auto e = v.read_irradiance(i);
    const render::RsmView view = v.rsm(i);
    const double pix = 2.0 * view.tan_half / rsm_size;
    const int base_block = static_cast<int>(centre.size());
    centre.resize(centre.size() + static_cast<std::size_t>(bs * bs), glm::dvec3(0.0));
    weight.resize(centre.size(), 0.0);
    for (int row = 0; row < rsm_size; ++row)
      for (int col = 0; col < rsm_size; ++col) {
        const std::size_t t = static_cast<std::size_t>(row * rsm_size + col);
        if (!rsm[t].valid) continue;
        const glm::dvec3 y(rsm[t].px, rsm[t].py, rsm[t].pz), n(rsm[t].nx, rsm[t].ny, rsm[t].nz);
        const glm::dvec3 d = y - view.origin;
        const double dist = glm::length(d), ca = glm::dot(d / dist, view.forward);
        const double nw = std::abs(glm::dot(n, -d / dist));
        const double a = pix * pix * ca * ca * ca * dist * dist;
        const glm::dvec3 ev(e[t].x, e[t].y, e[t].z);
        const glm::dvec3 phi = ev * (a / std::max(nw, 0.05));
        if (!(lum(phi) > 0.0)) continue;
        out.flux += lum(phi);
        out.flux_unclamped += lum(ev) * a / std::max(nw, 1e-3);
        Vpl p{y, n, -d / dist, phi, material_of(rsm[t]), base_block + (row / merge) * bs + col / merge};
        centre[static_cast<std::size_t>(p.block)] += lum(phi) * y;
        weight[static_cast<std::size_t>(p.block)] += lum(phi);
        vpls.push_back(p);
      }
  }
  for (std::size_t b = 0; b < centre.size(); ++b)
    if (weight[b] > 0.0) centre[b] /= weight[b];
  std::stable_sort(vpls.begin(), vpls.end(), [](const Vpl& a, const Vpl& b) { return a.block < b.block; });
  out.vpls = static_cast<int>(vpls.size());
  out.diffuse.assign(pixels.size(), 0.0);
  out.specular.assign(pixels.size(), 0.0);
  out.diffuse_sg.assign(pixels.size(), 0.0);
  const double ah2 = kPi * (1.0 - std::exp(-2.0));  // A_h(2) = 2 pi (1 - e^{-2}) / 2
  std::unique_ptr<ref::RayScene> rays;
  if (geometry) rays = std::make_unique<ref::RayScene>(*geometry);

  auto work = [&](std::size_t first, std::size_t step) {
    for (std::size_t p = first; p < pixels.size(); p += step) {
      const NfSurface& s = pixels[p];
      if (!s.valid) continue;
      const glm::dvec3 x(s.px, s.py, s.pz), nx(s.nx, s.ny, s.nz), vx(s.vx, s.vy, s.vz);
      const ref::ShadingMaterial mx = material_of(s);
      glm::dvec3 ld(0.0), ls(0.0), lsg(0.0);
      int block = -1;
      bool lit = true;
      for (const Vpl& j : vpls) {
        const glm::dvec3 d = j.y - x;
        const double r2 = glm::dot(d, d);
        if (!(r2 > 1e-12)) continue;
        const glm::dvec3 w = d / std::sqrt(r2);
        const double cp = glm::dot(nx, w), cj = -glm::dot(j.n, w);
        if (cp <= 0.0 || cj <= 0.0) continue;
        if (rays && j.block != block) {
          block = j.block;
          const glm::dvec3 c = centre[static_cast<std::size_t>(block)] - x;
          const double dc = glm::length(c);
          const double eps = 1e-3 * std::max(1.0, rays->scale());
          lit = dc <= 3.0 * eps || !rays->occluded(x + nx * eps, c / dc, eps, dc - 3.0 * eps);
        }
        if (!lit) continue;
        const glm::dvec3 fx = ref::brdf_eval(mx, nx, vx, w) * cp / r2;
        const glm::dvec3 fj = ref::brdf_eval(j.m, j.n, j.l, -w);
        const glm::dvec3 fjd = diffuse_part(j.m, j.n, j.l, -w);
        ld += fx * j.phi * fjd * cj;
        lsg += fx * j.phi * diffuse_part(j.m, j.n, j.l, j.n) * (kPi * std::exp(2.0 * (cj - 1.0)) / ah2);
        ls += fx * j.phi * (fj - fjd) * cj;
      }
      out.diffuse[p] = lum(ld);
      out.specular[p] = lum(ls);
      out.diffuse_sg[p] = lum(lsg);
    }
  };
  const int n = std::max(1, threads);
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(work, static_cast<std::size_t>(t), static_cast<std::size_t>(n));
  work(0, static_cast<std::size_t>(n));
  for (auto& t : pool) t.join();
  return out;
}

}  // namespace nf::bench
