#include "gl/gbuffer.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "gl/shader.h"
#include "luminaire/parallel.h"

namespace nf::gl {

GBuffer::GBuffer(int width, int height)
    : fb_(width, height, {GL_RGBA32F, GL_RGBA32F, GL_RGBA32F}, true),
      program_(build_program("gbuffer.vert.glsl", "gbuffer.frag.glsl")) {
  const auto bytes = static_cast<GLsizeiptr>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 16);
  glCreateBuffers(3, pack_);
  for (unsigned b : pack_) glNamedBufferData(b, bytes, nullptr, GL_STREAM_READ);
}

GBuffer::~GBuffer() {
  glDeleteBuffers(3, pack_);
  if (program_) glDeleteProgram(program_);
}

void GBuffer::render(const SceneGpu& scene, const scene::Camera& camera) {
  if (camera.width != width() || camera.height != height())
    fail(
        fmt::format("G-buffer is {}x{} but the camera asks for {}x{}", width(), height(), camera.width, camera.height));
  ReversedZScope depth_state;
  fb_.bind();
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(fb_.id(), GL_COLOR, i, zero);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(program_);
  scene.draw(camera_projection(camera) * camera_view(camera), true, false);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

namespace {

// Attachment `index` as RGBA floats in GL row order (row 0 = bottom) into pixel-pack buffer `pack`.
void read_into(unsigned fbo, int index, unsigned pack, int w, int h) {
  glNamedFramebufferReadBuffer(fbo, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + index));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pack);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

// Output pixel (x, y from the top) from GL row h - 1 - y of the three attachments.
NfSurface convert_surface(const float* pos, const float* nrm, const float* mat,
                          const std::vector<scene::Material>& materials, const scene::Camera& camera, int w, int h,
                          std::size_t x, std::size_t y) {
  const std::size_t i = (static_cast<std::size_t>(h) - 1 - y) * static_cast<std::size_t>(w) + x;
  NfSurface s{};
  const float* p = &pos[4 * i];
  const int id = static_cast<int>(std::lround(p[3])) - 1;
  if (id >= 0 && id < static_cast<int>(materials.size())) {
    const float* q = &nrm[4 * i];
    const float* m = &mat[4 * i];
    s.px = p[0];
    s.py = p[1];
    s.pz = p[2];
    s.valid = 1;
    glm::dvec3 nn(q[0], q[1], q[2]);
    const double len = glm::length(nn);
    nn = len > 0.0 ? nn / len : glm::dvec3(0.0, 0.0, 1.0);
    s.nx = static_cast<float>(nn.x);
    s.ny = static_cast<float>(nn.y);
    s.nz = static_cast<float>(nn.z);
    const glm::dvec3 v = glm::normalize(camera.position - glm::dvec3(p[0], p[1], p[2]));
    s.vx = static_cast<float>(v.x);
    s.vy = static_cast<float>(v.y);
    s.vz = static_cast<float>(v.z);
    const scene::MaterialKind kind = materials[static_cast<std::size_t>(id)].kind;
    const bool ggx = kind == scene::MaterialKind::ggx;
    s.brdf = ggx ? NF_BRDF_GGX : NF_BRDF_LAMBERT;
    s.base_r = m[0];
    s.base_g = m[1];
    s.base_b = m[2];
    s.roughness = ggx ? m[3] : 1.0f;
    s.metallic = ggx ? q[3] : 0.0f;
    if (kind == scene::MaterialKind::kurt) {  // base = world tangent, metallic = table index
      s.brdf = NF_BRDF_KURT;
      s.roughness = 1.0f;
      s.metallic = static_cast<float>(id);
    }
  }
  return s;
}

}  // namespace

std::vector<NfSurface> GBuffer::read_surfaces(const std::vector<scene::Material>& materials,
                                              const scene::Camera& camera) const {
  const int w = width(), h = height();
  const std::size_t bytes = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 16;
  for (int k = 0; k < 3; ++k) read_into(fb_.id(), k, pack_[k], w, h);
  const float* data[3] = {nullptr, nullptr, nullptr};
  for (int k = 0; k < 3; ++k) {
    data[k] = static_cast<const float*>(
        glMapNamedBufferRange(pack_[k], 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT));
    if (!data[k]) {
      for (int j = 0; j < k; ++j) glUnmapNamedBuffer(pack_[j]);
      fail(fmt::format("G-buffer read-back: mapping pixel-pack buffer {} failed (GL error 0x{:x})", k,
                       static_cast<unsigned>(glGetError())));
    }
  }
  const float *pos = data[0], *nrm = data[1], *mat = data[2];
  std::vector<NfSurface> out(static_cast<std::size_t>(w) * h);
  // Rows convert independently, each into its own slots, on every core: the per-pixel conversion in
  // double precision is host work that a moving camera pays every frame.
  lum::parallel_for(h, 0, [&](int row) {
    const std::size_t y = static_cast<std::size_t>(row);
    for (std::size_t x = 0; x < static_cast<std::size_t>(w); ++x)
      out[y * static_cast<std::size_t>(w) + x] = convert_surface(pos, nrm, mat, materials, camera, w, h, x, y);
  });
  for (unsigned b : pack_) glUnmapNamedBuffer(b);
  return out;
}

void GBuffer::write_surfaces(const std::vector<NfSurface>& surfaces) {
  const int w = width(), h = height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (surfaces.size() != n) fail(fmt::format("G-buffer is {}x{} but {} surfaces were given", w, h, surfaces.size()));
  std::vector<float> pos(4 * n), nrm(4 * n), mat(4 * n);
  for (std::size_t o = 0; o < n; ++o) {
    const NfSurface& s = surfaces[o];
    if (!s.valid) continue;
    // GL row h - 1 - y holds output row y.
    const std::size_t x = o % static_cast<std::size_t>(w), y = o / static_cast<std::size_t>(w);
    const std::size_t i = 4 * ((static_cast<std::size_t>(h) - 1 - y) * static_cast<std::size_t>(w) + x);
    const float p[4] = {s.px, s.py, s.pz, 1.0f}, q[4] = {s.nx, s.ny, s.nz, s.metallic},
                m[4] = {s.base_r, s.base_g, s.base_b, s.roughness};
    std::copy_n(p, 4, &pos[i]);
    std::copy_n(q, 4, &nrm[i]);
    std::copy_n(m, 4, &mat[i]);
  }
  const std::vector<float>* data[3] = {&pos, &nrm, &mat};
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  for (int k = 0; k < 3; ++k) glTextureSubImage2D(fb_.texture(k), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, data[k]->data());
}

std::vector<MemoryItem> GBuffer::memory() const {
  const std::size_t px = static_cast<std::size_t>(width()) * height();
  return {{"gbuffer position (RGBA32F)", px * 16},
          {"gbuffer normal (RGBA32F)", px * 16},
          {"gbuffer material (RGBA32F)", px * 16},
          {"gbuffer depth (D32F)", px * 4},
          {"gbuffer read-back (3 pixel-pack buffers)", px * 48}};
}

}  // namespace nf::gl
