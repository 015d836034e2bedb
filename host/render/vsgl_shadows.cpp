#include "render/vsgl_shadows.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "cl/buffers.h"
#include "core/error.h"
#include "core/memory.h"
#include "gl/point_shadow_maps.h"
#include "render/vsgl_contribution.h"
#include "render/vsgl_kernels.h"

namespace nf::render {

std::vector<int> strongest_vsgls(const std::vector<NfVsgl>& vsgls, int per_instance, int k) {
  std::vector<int> index(vsgls.size(), -1);
  if (per_instance < 1 || k < 1) return index;
  int next = 0;
  for (std::size_t first = 0; first < vsgls.size(); first += static_cast<std::size_t>(per_instance)) {
    const std::size_t end = std::min(vsgls.size(), first + static_cast<std::size_t>(per_instance));
    std::vector<std::size_t> order;
    for (std::size_t j = first; j < end; ++j)
      if (vsgls[j].power > 0.0f && std::isfinite(vsgls[j].power)) order.push_back(j);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return vsgls[a].power > vsgls[b].power; });
    const std::size_t take = std::min(order.size(), static_cast<std::size_t>(k));
    for (std::size_t t = 0; t < take; ++t) index[order[t]] = next++;
  }
  return index;
}

glm::dvec3 vsgl_shadow_origin(const NfVsgl& g, const VsglRsmRef& rsm, double lift) {
  const glm::dvec3 mu(g.mu_x, g.mu_y, g.mu_z);
  if (rsm.view && rsm.surfaces && rsm.size > 0 &&
      rsm.surfaces->size() == static_cast<std::size_t>(rsm.size) * static_cast<std::size_t>(rsm.size)) {
    int c = 0, r = 0;
    if (rsm_texel_of(*rsm.view, rsm.size, mu, c, r)) {
      const NfSurface& s = (*rsm.surfaces)[static_cast<std::size_t>(r) * static_cast<std::size_t>(rsm.size) +
                                           static_cast<std::size_t>(c)];
      const glm::dvec3 y(s.px, s.py, s.pz), n(s.nx, s.ny, s.nz);
      const double dy = glm::length(y - rsm.view->origin), dmu = glm::length(mu - rsm.view->origin);
      const double len = glm::length(n);
      if (s.valid && len > 1e-6 && std::isfinite(len) && dmu > dy + 1e-3 + 1e-3 * dy) return y + n * (lift / len);
    }
  }
  const glm::dvec3 n(g.xd_x, g.xd_y, g.xd_z);
  const double len = glm::length(n);
  if (!(len > 1e-6) || !std::isfinite(len)) return mu;
  return mu + n * (lift / len);
}

int vsgl_shadow_max(int instances, int size) {
  const std::size_t per = gl::PointShadowMaps::bytes_for(static_cast<std::size_t>(std::max(instances, 1)), size);
  return static_cast<int>(kVsglShadowMaxBytes / per);
}

VsglShadows::VsglShadows(cl::Runtime& rt, VsglShadowParams p) : rt_(rt), p_(p) { upload({}); }

VsglShadows::~VsglShadows() = default;

cl_float4 VsglShadows::bias() const {
  return cl_float4{{static_cast<float>(p_.constant), static_cast<float>(p_.depth_texels),
                    static_cast<float>(p_.normal_texels), 0.0f}};
}

std::size_t VsglShadows::device_bytes() const {
  return maps_bytes_ + index_.size() * sizeof(int) + origins_.size() * sizeof(cl_float4);
}

void VsglShadows::upload(const std::vector<float>& maps) {
  index_buf_ = cl::upload(rt_, index_.empty() ? std::vector<int>{-1} : index_, "uploading the VSGL shadow indices");
  maps_buf_ = cl::upload(rt_, maps, "uploading the VSGL shadow maps");
  std::vector<cl_float4> o;
  for (const auto& v : origins_)
    o.push_back(cl_float4{{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), 0.0f}});
  origins_buf_ = cl::upload(rt_, o, "uploading the VSGL shadow origins");
  maps_bytes_ = maps.size() * sizeof(float);
}

void VsglShadows::build_at(const gl::SceneGpu& scene, const std::vector<glm::dvec3>& origins) {
  if (!gl_) gl_ = std::make_unique<gl::PointShadowMaps>(p_.size, p_.near);
  origins_ = origins;
  gl_->render(scene, origins_);
  upload(gl_->maps());
}

void VsglShadows::build(const gl::SceneGpu& scene, const std::vector<NfVsgl>& vsgls, int per_instance, int k,
                        const std::vector<VsglRsmRef>& rsms) {
  const int instances = per_instance > 0
                            ? static_cast<int>((vsgls.size() + static_cast<std::size_t>(per_instance) - 1) /
                                               static_cast<std::size_t>(per_instance))
                            : 0;
  const int k_max = vsgl_shadow_max(instances, p_.size);
  k = std::min(k, per_instance);  // more than N_v: every VSGL
  if (k > k_max)
    fail(
        fmt::format("vsgl_shadowed: {} shadowed VSGLs x {} instance(s) x 6 faces x {}^2 texels x 4 bytes = {}, over "
                    "the maximum of {} for the shadow maps (at most {} per instance here)",
                    k, instances, p_.size,
                    format_bytes(gl::PointShadowMaps::bytes_for(
                        static_cast<std::size_t>(k) * static_cast<std::size_t>(instances), p_.size)),
                    format_bytes(kVsglShadowMaxBytes), k_max));
  index_ = strongest_vsgls(vsgls, per_instance, k);
  origins_.clear();
  std::vector<std::size_t> owner;
  for (std::size_t j = 0; j < index_.size(); ++j)
    if (index_[j] >= 0) {
      if (origins_.size() <= static_cast<std::size_t>(index_[j]))
        origins_.resize(static_cast<std::size_t>(index_[j]) + 1);
      const std::size_t inst = j / static_cast<std::size_t>(per_instance);
      const VsglRsmRef rsm = inst < rsms.size() ? rsms[inst] : VsglRsmRef{};
      origins_[static_cast<std::size_t>(index_[j])] = vsgl_shadow_origin(vsgls[j], rsm, p_.lift);
    }
  // host readback and device copy (PoCL: host memory too)
  check_memory("vsgl_shadowed", fmt::format("{} VSGL cube shadow maps of {}^2 per face", origins_.size(), p_.size),
               2 * gl::PointShadowMaps::bytes_for(origins_.size(), p_.size), available_host_memory());
  if (origins_.empty()) {
    upload({});
    return;
  }
  if (!gl_) gl_ = std::make_unique<gl::PointShadowMaps>(p_.size, p_.near);
  gl_->render(scene, origins_);
  upload(gl_->maps());
}

std::vector<float> VsglShadows::lookup(const std::vector<glm::dvec3>& points, const std::vector<glm::dvec3>& normals,
                                       const std::vector<int>& light) {
  if (points.size() != normals.size() || points.size() != light.size())
    fail("VSGL shadow lookup: points, normals and lights differ in number");
  for (int l : light)
    if (l < 0 || l >= maps_count()) fail(fmt::format("VSGL shadow lookup: map {} of {}", l, maps_count()));
  std::vector<cl_float4> p, n;
  for (std::size_t i = 0; i < points.size(); ++i) {
    p.push_back(cl_float4{
        {static_cast<float>(points[i].x), static_cast<float>(points[i].y), static_cast<float>(points[i].z), 0.0f}});
    n.push_back(cl_float4{
        {static_cast<float>(normals[i].x), static_cast<float>(normals[i].y), static_cast<float>(normals[i].z), 0.0f}});
  }
  const ::cl::Buffer pb = cl::upload(rt_, p, "uploading lookup points");
  const ::cl::Buffer nb = cl::upload(rt_, n, "uploading lookup normals");
  const ::cl::Buffer lb = cl::upload(rt_, light, "uploading lookup lights");
  ::cl::Buffer out;
  cl::call([&] { out = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, std::max<std::size_t>(points.size(), 1) * 4); },
           "VSGL shadow lookup output");
  vsgl_kernels::ShadowLookup kern(rt_, "vsgl.cl", "vsgl_shadow_lookup");
  kern.bind(pb, nb, lb, static_cast<int>(points.size()), maps_buf_, origins_buf_, p_.size, static_cast<float>(p_.near),
            bias(), out);
  rt_.launch(kern.get(), ::cl::NDRange(std::max<std::size_t>(points.size(), 1)));
  std::vector<float> v(points.size());
  if (!v.empty())
    cl::call([&] { rt_.queue().enqueueReadBuffer(out, CL_TRUE, 0, v.size() * sizeof(float), v.data()); },
             "reading the VSGL shadow lookup");
  return v;
}

}  // namespace nf::render
