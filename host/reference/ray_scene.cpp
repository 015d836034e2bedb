#include "reference/ray_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include "core/error.h"

namespace nf::ref {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

RayScene::RayScene(const scene::Geometry& geometry) : impl_(std::make_unique<Impl>()), geometry_(&geometry) {
  impl_->device = rtcNewDevice("threads=1");
  if (!impl_->device)
    fail(fmt::format("Embree: cannot create a device (error {})", static_cast<int>(rtcGetDeviceError(nullptr))));
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  world_.resize(geometry.instances.size());
  for (std::size_t i = 0; i < geometry.instances.size(); ++i) {
    const scene::Instance& inst = geometry.instances[i];
    const scene::Mesh& mesh = geometry.meshes[static_cast<std::size_t>(inst.mesh)];
    auto& w = world_[i];
    w.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) {
      w.push_back(glm::dvec3(inst.to_world * glm::dvec4(glm::dvec3(p), 1.0)));
      for (int k = 0; k < 3; ++k) scale_ = std::max(scale_, std::abs(w.back()[k]));
    }
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), std::max<std::size_t>(w.size(), 1)));
    for (std::size_t v = 0; v < w.size(); ++v)
      for (int k = 0; k < 3; ++k) vb[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(w[v][k]);
    const std::size_t tris = mesh.triangle_count();
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), std::max<std::size_t>(tris, 1)));
    for (std::size_t t = 0; t < 3 * tris; ++t) ib[t] = mesh.indices[t];
    if (tris == 0) ib[0] = ib[1] = ib[2] = 0;
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(impl_->scene, g, static_cast<unsigned>(i));
    rtcReleaseGeometry(g);
    triangles_ += tris;
  }
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) fail("Embree: building the scene failed");
}

RayScene::~RayScene() = default;

namespace {
RTCRay make_ray(glm::dvec3 o, glm::dvec3 d, double tmin, double tmax) {
  RTCRay r{};
  r.org_x = static_cast<float>(o.x);
  r.org_y = static_cast<float>(o.y);
  r.org_z = static_cast<float>(o.z);
  r.dir_x = static_cast<float>(d.x);
  r.dir_y = static_cast<float>(d.y);
  r.dir_z = static_cast<float>(d.z);
  r.tnear = static_cast<float>(tmin);
  r.tfar = tmax >= static_cast<double>(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
                                                                          : static_cast<float>(tmax);
  r.mask = 0xffffffffu;
  r.flags = 0;
  return r;
}
}  // namespace

RayHit RayScene::intersect(glm::dvec3 origin, glm::dvec3 direction, double tmin, double tmax) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray = make_ray(origin, direction, tmin, tmax);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  RayHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.instance = static_cast<int>(rh.hit.geomID);
  h.triangle = static_cast<int>(rh.hit.primID);
  h.b1 = rh.hit.u;
  h.b2 = rh.hit.v;
  return h;
}

bool RayScene::occluded(glm::dvec3 origin, glm::dvec3 direction, double tmin, double tmax) const {
  if (!(tmax > tmin)) return false;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r = make_ray(origin, direction, tmin, tmax);
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

void RayScene::triangle(int instance, int tri, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c) const {
  const scene::Instance& inst = geometry_->instances[static_cast<std::size_t>(instance)];
  const scene::Mesh& mesh = geometry_->meshes[static_cast<std::size_t>(inst.mesh)];
  const auto& w = world_[static_cast<std::size_t>(instance)];
  const std::size_t k = 3 * static_cast<std::size_t>(tri);
  a = w[mesh.indices[k]];
  b = w[mesh.indices[k + 1]];
  c = w[mesh.indices[k + 2]];
}

}  // namespace nf::ref
