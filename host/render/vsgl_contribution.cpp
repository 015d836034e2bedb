#include "render/vsgl_contribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/timer.h"
#include "gl/gbuffer.h"
#include "gl/scene_gpu.h"
#include "gl/shadow_maps.h"
#include "render/kurt_table.h"
#include "render/vsgl_debug_view.h"
#include "render/vsgl_kernels.h"
#include "render/vsgl_split.h"

namespace nf::render {

static_assert(sizeof(NfVsgl) == 96, "NfVsgl layout (kernels/shared/vsgl.h)");
static_assert(offsetof(NfVsgl, cs_r) == 48 && offsetof(NfVsgl, level) == 80, "NfVsgl layout");

namespace {

using cl::download;  // the shared buffer helpers (cl/buffers.h)
using cl::make_buffer;
using cl::upload_rw;

// Texels of one pyramid of a size^2 RSM (every level down to 1 x 1).
std::size_t pyramid_texels(int size) {
  std::size_t texels = 0;
  for (int s = size; s >= 1; s /= 2) texels += static_cast<std::size_t>(s) * static_cast<std::size_t>(s);
  return texels;
}

cl_float4 f4(glm::dvec3 v) {
  return cl_float4{{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), 0.0f}};
}

// What the RSMs and VSGLs depend on: the light-field sampling settings (the RSMs' irradiance is
// the light-field estimate at the first frame index and band), the indirect settings and the
// lights; materials through set_materials().
const Depends kDepends{.settings = {"luminaires", "indirect"}, .lights = true, .first_frame = true, .band = true};

}  // namespace

VsglSettings vsgl_settings(const FrameSettings& f) {
  const auto& d = f.declared;
  VsglSettings s;
  s.rsm_size = d.rsm_size;
  s.count = d.vsgl_count;
  // the kernel codes of the typed choices (shared/vsgl.h)
  s.kernel = scene::choice_value<scene::VsglKernel>(d.vsgl_kernel) == scene::VsglKernel::point
                 ? NF_VSGL_KERNEL_POINT
                 : NF_VSGL_KERNEL_INTEGRAL;
  s.k = d.vsgl_k;
  s.points = scene::choice_value<scene::VsglPoints>(d.vsgl_points) == scene::VsglPoints::fibonacci
                 ? NF_VSGL_POINTS_FIBONACCI
                 : NF_VSGL_POINTS_HAMMERSLEY;
  s.shadowed = d.vsgl_shadowed;
  // as declared (scene/settings.cpp): settings set in code are checked like a scene file's
  for (const char* name : {"rsm_size", "vsgl_count", "vsgl_k", "vsgl_shadowed"})
    scene::check_setting(d, name, "indirect");
  s.classes = scene::choice_value<scene::VsglSplit>(d.vsgl_split) == scene::VsglSplit::none ? 1 : 6;
  return s;
}

// The instance's world -> local map is rigid (Renderer checks): local = R p + t, so the world
// position of a local point q is R^T (q - t) and a local direction d is R^T d.
RsmView rsm_view(const NfLuminaire& lum, const NfInstance& in) {
  glm::dmat3 r(0.0);
  glm::dvec3 t(0.0);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[j][i] = in.to_local[4 * i + j];  // glm: column j, row i
    t[i] = in.to_local[4 * i + 3];
  }
  const glm::dmat3 rt = glm::transpose(r);
  const double cells_x = lum.count_x + lum.support - 1, cells_y = lum.count_y + lum.support - 1;
  const glm::dvec3 centre(lum.basis_origin_x + 0.5 * cells_x * lum.cell_x,
                          lum.basis_origin_y + 0.5 * cells_y * lum.cell_y, -static_cast<double>(lum.delta));
  RsmView v;
  v.origin = rt * (centre - t);
  v.forward = glm::normalize(rt * glm::dvec3(0, 0, 1));
  v.up = glm::normalize(rt * glm::dvec3(0, 1, 0));
  // The frustum that holds every direction the light field emits in (docs/indirect.md "RSM"),
  // made symmetric about +z so that the RSM is a plain square camera.
  const gl::ShadowFrustum f = gl::shadow_frustum_for(lum);
  v.tan_half = std::max({std::abs(f.left), std::abs(f.right), std::abs(f.bottom), std::abs(f.top)});
  return v;
}

scene::Camera rsm_camera(const RsmView& view, int size) {
  scene::Camera cam;
  cam.position = view.origin;
  cam.target = view.origin + view.forward;
  cam.up = view.up;
  cam.fov_y_deg = 2.0 * std::atan(view.tan_half) * 180.0 / 3.14159265358979323846;
  cam.width = cam.height = size;
  cam.near = 0.01;
  return cam;
}

bool rsm_texel_of(const RsmView& view, int size, const glm::dvec3& p, int& column, int& row) {
  const scene::Camera cam = rsm_camera(view, size);
  const glm::dvec3 d = p - cam.position;
  const double z = glm::dot(d, cam.forward());
  if (!(z > 0.0)) return false;
  const double t = cam.tan_half_fov_y();
  const double x = glm::dot(d, cam.right()) / (z * t), y = glm::dot(d, cam.true_up()) / (z * t);
  const double c = std::floor(0.5 * (x + 1.0) * size), r = std::floor(0.5 * (1.0 - y) * size);
  if (!(c >= 0.0 && c < size && r >= 0.0 && r < size)) return false;
  column = static_cast<int>(c);
  row = static_cast<int>(r);
  return true;
}

VsglContribution::VsglContribution(cl::Runtime& rt, const scene::Scene& scene)
    : rt_(rt), scene_(scene), sampler_(rt), shadows_(std::make_unique<VsglShadows>(rt)) {
  kurt_ = kurt_table(scene.geometry.materials);
  kurt_buf_ = upload_rw(rt_, kurt_, "uploading the Kurt material table (indirect)");
  sampler_.set_mean_direction(true);  // each texel's incident direction (kernels/vsgl.cl vsgl_texels)
}

VsglContribution::~VsglContribution() = default;

// scene_ is the Renderer's scene, whose materials are already the new ones.
void VsglContribution::set_materials(const std::vector<scene::Material>& materials) {
  kurt_ = kurt_table(materials);
  kurt_buf_ = upload_rw(rt_, kurt_, "uploading the Kurt material table (indirect)");
  if (scene_gpu_) scene_gpu_->set_materials(scene_.geometry);
  key_.clear();
}

const std::vector<NfSurface>& VsglContribution::rsm_surfaces(int i) const {
  return rsms_.at(static_cast<std::size_t>(i)).surfaces;
}
DebugViewInfo VsglContribution::debug_view_info() {
  return {"VSGL", "VSGLs", "instance 0's RSM irradiance with its VSGLs (docs/indirect.md)",
          "RSM irradiance (log, auto range); white: VSGL centres, magenta: sigma"};
}

DebugImage VsglContribution::debug_view(const std::string& name) {
  if (name != debug_view_info().name) return Contribution::debug_view(name);
  if (instances() == 0 || vsgls().empty()) return {};
  const std::vector<glm::vec4> e = read_irradiance(0);
  const int size = static_cast<int>(std::lround(std::sqrt(static_cast<double>(e.size()))));
  const std::size_t per = vsgls().size() / static_cast<std::size_t>(instances());
  const std::vector<NfVsgl> v0(vsgls().begin(), vsgls().begin() + static_cast<std::ptrdiff_t>(per));
  return vsgl_debug_data(e, size, v0, rsm(0));
}

const RsmView& VsglContribution::rsm(int i) const { return rsms_.at(static_cast<std::size_t>(i)).view; }

void VsglContribution::ensure_gl(int size) {
  if (!scene_gpu_) scene_gpu_ = std::make_unique<gl::SceneGpu>(scene_.geometry);
  if (!gbuffer_ || gbuffer_->width() != size) {
    gbuffer_.reset();
    gbuffer_ = std::make_unique<gl::GBuffer>(size, size);
  }
}

::cl::Buffer VsglContribution::pyramid_buffer(int size, int classes) {
  const std::size_t texels = pyramid_texels(size) * static_cast<std::size_t>(std::max(classes, 1));
  return make_buffer(rt_, CL_MEM_READ_WRITE, texels * NF_VSGL_QUANTITIES * sizeof(cl_float4), nullptr,
                     "VSGL pyramid buffer");
}

void VsglContribution::run_texels(const ::cl::Buffer& surf, const ::cl::Buffer& irradiance, int size,
                                  const RsmView& view, const ::cl::Buffer& pyr, const ::cl::Buffer* dir, int classes) {
  vsgl_kernels::Texels k(rt_, "vsgl.cl", "vsgl_texels");
  const float pix = static_cast<float>(2.0 * view.tan_half / size);
  k.bind(surf, irradiance, kurt_buf_, static_cast<int>(kurt_.size()), size, f4(view.origin), f4(view.forward), pix, pyr,
         dir ? *dir : irradiance, dir ? 1 : 0, classes, static_cast<int>(pyramid_texels(size)));
  rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(size), static_cast<std::size_t>(size)));
}

std::vector<int> VsglContribution::run_pyramid(const ::cl::Buffer& pyr, int size, int classes, bool split) {
  const int stride = static_cast<int>(pyramid_texels(size));
  if (classes > 1 && !split) {
    vsgl_kernels::Split k(rt_, "vsgl.cl", "vsgl_split");
    k.bind(pyr, size, classes, stride);
    rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(size), static_cast<std::size_t>(size)));
  }
  vsgl_kernels::PyramidDown k(rt_, "vsgl.cl", "vsgl_pyramid_down");
  std::vector<int> off{0};
  for (int s = size; s > 1; s /= 2) off.push_back(off.back() + s * s);
  for (int c = 0; c < classes; ++c)
    for (std::size_t l = 0; l + 1 < off.size(); ++l) {
      const int s = size >> l;
      k.bind(pyr, c * stride + off[l], s, c * stride + off[l + 1]);
      rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(s / 2), static_cast<std::size_t>(s / 2)));
    }
  return off;
}

// Each class's VSGLs are generated from its own pyramid (the kernel takes the class's total from
// its top level), N_c of them (vsgl_class_counts of the classes' PDF masses), written one class
// after the other.
void VsglContribution::run_generate(const ::cl::Buffer& pyr, const std::vector<int>& offsets, int size, int classes,
                                    glm::dvec3 origin, const VsglSettings& s, const ::cl::Buffer& out) {
  vsgl_kernels::Generate k(rt_, "vsgl.cl", "vsgl_generate");
  const int stride = static_cast<int>(pyramid_texels(size));
  std::vector<double> totals(static_cast<std::size_t>(classes), 0.0);
  for (int c = 0; c < classes; ++c) {
    const auto top =
        download<glm::vec4>(rt_, pyr, 1, static_cast<std::size_t>(c * stride + offsets.back()) * NF_VSGL_QUANTITIES,
                            "reading a VSGL class total");
    totals[static_cast<std::size_t>(c)] = top[0].w;
  }
  const std::vector<int> counts = classes > 1 ? vsgl_class_counts(totals, s.count) : std::vector<int>{s.count};
  std::vector<::cl::Buffer> offs;  // kept alive until the launches have finished
  int first = 0;
  for (int c = 0; c < classes; ++c) {
    const int n = counts[static_cast<std::size_t>(c)];
    if (n <= 0) continue;
    std::vector<int> o = offsets;
    for (int& v : o) v += c * stride;
    offs.push_back(upload_rw(rt_, o, "VSGL pyramid offsets"));
    k.bind(pyr, offs.back(), size, static_cast<int>(offsets.size()), n, s.kernel, static_cast<float>(s.k), s.points,
           f4(origin), out, first);
    rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(n)));
    first += n;
  }
  cl::call([&] { rt_.queue().finish(); }, "VSGL generation");
}

std::vector<glm::vec4> VsglContribution::read_summed(const ::cl::Buffer& pyr, const std::vector<int>& offsets,
                                                     int size0, int classes, int level, int q) {
  const int size = size0 >> level;
  const std::size_t n = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  const std::size_t stride = pyramid_texels(size0);
  std::vector<glm::vec4> out(n, glm::vec4(0.0f));
  for (int c = 0; c < classes; ++c) {
    const auto all = download<glm::vec4>(
        rt_, pyr, n * NF_VSGL_QUANTITIES,
        (static_cast<std::size_t>(c) * stride + static_cast<std::size_t>(offsets.at(static_cast<std::size_t>(level)))) *
            NF_VSGL_QUANTITIES,
        "reading a VSGL pyramid level");
    for (std::size_t t = 0; t < n; ++t) out[t] += all[NF_VSGL_QUANTITIES * t + static_cast<std::size_t>(q)];
  }
  return out;
}

void VsglContribution::run_shade(const ::cl::Buffer& surfaces, int count, const ::cl::Buffer& vsgls, int nv,
                                 const ::cl::Buffer& out, const VsglShadows& shadows, const ::cl::Buffer& index) {
  vsgl_kernels::Shade k(rt_, "vsgl.cl", "vsgl_shade");
  k.bind(surfaces, count, vsgls, nv, kurt_buf_, static_cast<int>(kurt_.size()), out, index, shadows.maps(),
         shadows.origins(), shadows.params().size, static_cast<float>(shadows.params().near), shadows.bias());
  const ::cl::Event ev = rt_.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(std::max(count, 1))));
  cl::call([&] { ev.wait(); }, "VSGL shading kernel");
}

bool VsglContribution::build(const FrameInputs& in) {
  const VsglSettings vs = vsgl_settings(in.settings);
  SamplingSettings ss = in.settings.sampling;  // fixed frame index: the VSGLs do not flicker by themselves
  const InputKey key(kDepends, in);
  if (key == key_) return false;
  times_ = {};
  const int size = vs.rsm_size;
  const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  rsms_.resize(in.lights.size());
  for (std::size_t i = 0; i < in.lights.size(); ++i) {
    Rsm& r = rsms_[i];
    const LightInstance& li = in.lights[i];
    // 1. the RSM: the G-buffer pass from the U grid's centre
    Timer timer;
    r.view = rsm_view(li.luminaire->params(), li.instance);
    ensure_gl(size);
    const scene::Camera cam = rsm_camera(r.view, size);
    gbuffer_->render(*scene_gpu_, cam);
    r.surfaces = gbuffer_->read_surfaces(scene_.geometry.materials, cam);
    std::vector<NfSurface> irr = r.surfaces;
    for (auto& s : irr) s.brdf = NF_BRDF_IRRADIANCE;
    r.surf_buf = upload_rw(rt_, r.surfaces, "uploading an RSM");
    r.irr_buf = upload_rw(rt_, irr, "uploading an RSM");
    times_.rsm_ms += timer.ms();
    // 2. E(y_j) by the light-field estimator (no visibility: the RSM holds what the luminaire's
    //    centre sees)
    timer.reset();
    LightInstance one = li;
    one.visibility = nullptr;
    one.vis_words = 0;
    sampler_.run(r.irr_buf, static_cast<int>(texels), std::span<const LightInstance>(&one, 1), ss);
    times_.light_ms += timer.ms();
    // 3. quantities and pyramid
    timer.reset();
    r.classes = vs.classes;
    r.pyr = pyramid_buffer(size, r.classes);
    run_texels(r.surf_buf, sampler_.radiance(), size, r.view, r.pyr, &sampler_.direction(), r.classes);
    r.offsets = run_pyramid(r.pyr, size, r.classes, true);
    cl::call([&] { rt_.queue().finish(); }, "VSGL pyramid");
    times_.pyramid_ms += timer.ms();
    // keep E for introspection (the sampler's buffer is reused by the next instance)
    r.irr_buf = make_buffer(rt_, CL_MEM_READ_WRITE, texels * sizeof(cl_float4), nullptr, "RSM irradiance copy");
    cl::call([&] { rt_.queue().enqueueCopyBuffer(sampler_.radiance(), r.irr_buf, 0, 0, texels * sizeof(cl_float4)); },
             "copying the RSM irradiance");
  }
  // 4. VSGLs of every instance, one buffer
  Timer timer;
  const std::size_t nv = static_cast<std::size_t>(vs.count) * rsms_.size();
  vsgl_buf_ = make_buffer(rt_, CL_MEM_READ_WRITE, nv * sizeof(NfVsgl), nullptr, "VSGL buffer");
  vsgls_.clear();
  for (std::size_t i = 0; i < rsms_.size(); ++i) {
    const ::cl::Buffer part = make_buffer(rt_, CL_MEM_READ_WRITE, static_cast<std::size_t>(vs.count) * sizeof(NfVsgl),
                                          nullptr, "VSGL buffer");
    run_generate(rsms_[i].pyr, rsms_[i].offsets, size, rsms_[i].classes, rsms_[i].view.origin, vs, part);
    const auto v = download<NfVsgl>(rt_, part, static_cast<std::size_t>(vs.count), 0, "reading the VSGLs");
    vsgls_.insert(vsgls_.end(), v.begin(), v.end());
  }
  if (!vsgls_.empty())
    cl::call(
        [&] { rt_.queue().enqueueWriteBuffer(vsgl_buf_, CL_TRUE, 0, vsgls_.size() * sizeof(NfVsgl), vsgls_.data()); },
        "uploading the VSGLs");
  times_.generate_ms = timer.ms();
  // 5. shadow maps of the vsgl_shadowed strongest VSGLs of each instance
  timer.reset();
  if (vs.shadowed > 0 && !vsgls_.empty()) ensure_gl(size);
  if (scene_gpu_) {
    std::vector<VsglRsmRef> refs;
    for (const auto& r : rsms_) refs.push_back({&r.view, &r.surfaces, size});
    shadows_->build(*scene_gpu_, vsgls_, vs.count, vs.shadowed, refs);
  }
  times_.shadow_ms = timer.ms();
  pyr_bytes_ = pyramid_texels(size) * static_cast<std::size_t>(vs.classes) * NF_VSGL_QUANTITIES * sizeof(cl_float4);
  pyr_bytes_ = pyr_bytes_ * rsms_.size() + rsms_.size() * texels * (2 * sizeof(NfSurface) + sizeof(cl_float4));
  key_ = key;
  return true;
}

std::vector<glm::vec4> VsglContribution::read_irradiance(int i) {
  const Rsm& r = rsms_.at(static_cast<std::size_t>(i));
  return download<glm::vec4>(rt_, r.irr_buf, r.surfaces.size(), 0, "reading the RSM irradiance");
}

std::vector<glm::vec4> VsglContribution::read_level(int i, int level, int q) {
  const Rsm& r = rsms_.at(static_cast<std::size_t>(i));
  const int size0 = static_cast<int>(std::lround(std::sqrt(static_cast<double>(r.surfaces.size()))));
  return read_summed(r.pyr, r.offsets, size0, r.classes, level, q);
}

std::vector<NfVsgl> VsglContribution::generate(const std::vector<glm::vec4>& level0, int size, glm::dvec3 origin,
                                               const VsglSettings& s, std::vector<std::vector<glm::vec4>>* levels_out) {
  const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  if (size < 1 || (size & (size - 1)) != 0 || level0.size() != texels * NF_VSGL_QUANTITIES)
    fail(fmt::format("VSGL generation: {} quantities for a {}^2 RSM", level0.size(), size));
  const int classes = std::max(s.classes, 1);
  const ::cl::Buffer pyr = pyramid_buffer(size, classes);
  cl::call([&] { rt_.queue().enqueueWriteBuffer(pyr, CL_TRUE, 0, level0.size() * sizeof(cl_float4), level0.data()); },
           "uploading RSM quantities");
  const std::vector<int> off = run_pyramid(pyr, size, classes, false);
  if (levels_out) {
    levels_out->clear();
    for (std::size_t k = 0; k < off.size(); ++k) {
      const std::size_t n = static_cast<std::size_t>(size >> k);
      std::vector<glm::vec4> all(n * n * NF_VSGL_QUANTITIES, glm::vec4(0.0f));
      for (int q = 0; q < NF_VSGL_QUANTITIES; ++q) {
        const auto one = read_summed(pyr, off, size, classes, static_cast<int>(k), q);
        for (std::size_t t = 0; t < n * n; ++t) all[NF_VSGL_QUANTITIES * t + static_cast<std::size_t>(q)] = one[t];
      }
      levels_out->push_back(std::move(all));
    }
  }
  const ::cl::Buffer out =
      make_buffer(rt_, CL_MEM_READ_WRITE, static_cast<std::size_t>(s.count) * sizeof(NfVsgl), nullptr, "VSGL buffer");
  run_generate(pyr, off, size, classes, origin, s, out);
  return download<NfVsgl>(rt_, out, static_cast<std::size_t>(s.count), 0, "reading the VSGLs");
}

std::vector<glm::vec4> VsglContribution::texel_quantities(const std::vector<NfSurface>& surfaces,
                                                          const std::vector<glm::vec4>& e, int size,
                                                          const RsmView& view) {
  const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  if (surfaces.size() != texels || e.size() != texels)
    fail(fmt::format("VSGL texels: {} surfaces and {} irradiances for a {}^2 RSM", surfaces.size(), e.size(), size));
  const ::cl::Buffer sb = upload_rw(rt_, surfaces, "uploading RSM texels");
  const ::cl::Buffer eb = upload_rw(rt_, e, "uploading RSM irradiance");
  const ::cl::Buffer pyr = pyramid_buffer(size, 1);
  run_texels(sb, eb, size, view, pyr);
  return download<glm::vec4>(rt_, pyr, texels * NF_VSGL_QUANTITIES, 0, "reading RSM quantities");
}

std::vector<glm::vec4> VsglContribution::shade(const std::vector<NfSurface>& surfaces, const std::vector<NfVsgl>& vsgls,
                                               const VsglShadows* shadows) {
  const ::cl::Buffer sb = upload_rw(rt_, surfaces, "uploading surfaces");
  const ::cl::Buffer vb = upload_rw(rt_, vsgls, "uploading VSGLs");
  const ::cl::Buffer out =
      make_buffer(rt_, CL_MEM_READ_WRITE, std::max<std::size_t>(surfaces.size(), 1) * sizeof(cl_float4), nullptr,
                  "VSGL output buffer");
  const VsglShadows& sh = shadows ? *shadows : *shadows_;
  std::vector<int> index(vsgls.size(), -1);
  if (shadows) {
    if (shadows->index_host().size() != vsgls.size())
      fail(fmt::format("VSGL shading: shadow maps for {} VSGLs, {} given", shadows->index_host().size(), vsgls.size()));
    index = shadows->index_host();
  }
  const ::cl::Buffer ib = upload_rw(rt_, index, "uploading the VSGL shadow indices");
  run_shade(sb, static_cast<int>(surfaces.size()), vb, static_cast<int>(vsgls.size()), out, sh, ib);
  return download<glm::vec4>(rt_, out, surfaces.size(), 0, "reading the VSGL radiance");
}

// Compiles the kernels (and the estimator's, through one texel) so that no frame times a compiler.
void VsglContribution::prepare(const FrameInputs& in) {
  (void)vsgl_settings(in.settings);
  rt_.kernel("vsgl.cl", "vsgl_texels");
  rt_.kernel("vsgl.cl", "vsgl_pyramid_down");
  rt_.kernel("vsgl.cl", "vsgl_split");
  rt_.kernel("vsgl.cl", "vsgl_generate");
  rt_.kernel("vsgl.cl", "vsgl_shade");
  // refuse a k over the maximum before any frame (VsglShadows::build checks it again)
  const int k = std::min(in.settings.declared.vsgl_shadowed, in.settings.declared.vsgl_count);
  const int instances = static_cast<int>(in.lights.size());
  const int k_max = vsgl_shadow_max(instances, shadows_->params().size);
  if (instances > 0 && k > k_max)
    fail(
        fmt::format("vsgl_shadowed: {} per instance x {} instance(s) x 6 faces x {}^2 texels x 4 bytes is over the "
                    "maximum of {} for the VSGL shadow maps (at most {} per instance here)",
                    k, instances, shadows_->params().size, format_bytes(kVsglShadowMaxBytes), k_max));
  NfSurface s{};
  s.brdf = NF_BRDF_IRRADIANCE;
  const ::cl::Buffer one = upload_surfaces(rt_, {s});
  for (const auto& l : in.lights) {
    LightInstance li = l;
    li.visibility = nullptr;
    li.vis_words = 0;
    sampler_.run(one, 1, std::span<const LightInstance>(&li, 1), in.settings.sampling);
    break;
  }
}

ContributionFrame VsglContribution::add(const FrameInputs& in, std::vector<glm::vec4>& radiance) {
  ContributionFrame f;
  Timer wall;
  if (build(in)) {  // the build shows in the frame that did it
    f.step1_ms = times_.total();
    f.parts_ms = {{"rsm", times_.rsm_ms},
                  {"rsm_lighting", times_.light_ms},
                  {"pyramid", times_.pyramid_ms},
                  {"generation", times_.generate_ms},
                  {"vsgl shadow maps", times_.shadow_ms}};
  }
  const std::size_t n = static_cast<std::size_t>(std::max(in.count, 1));
  if (out_bytes_ != n * sizeof(cl_float4)) {
    out_ = make_buffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_float4), nullptr, "VSGL output buffer");
    out_bytes_ = n * sizeof(cl_float4);
  }
  Timer shade_timer;
  run_shade(in.surfaces, in.count, vsgl_buf_, static_cast<int>(vsgls_.size()), out_, *shadows_, shadows_->index());
  f.step2_ms = shade_timer.ms();
  f.wall_ms = wall.ms();
  Timer readback;
  add_radiance(radiance, read_radiance(rt_, out_, in.count, "reading the VSGL radiance"));
  f.samples = static_cast<std::uint64_t>(std::max(in.count, 0)) * vsgls_.size();
  f.readback_ms = readback.ms();
  return f;
}

std::size_t VsglContribution::device_bytes() const {
  return pyr_bytes_ + vsgls_.size() * sizeof(NfVsgl) + out_bytes_ + kurt_.size() * sizeof(NfKurtMaterial) +
         shadows_->device_bytes();
}

}  // namespace nf::render
