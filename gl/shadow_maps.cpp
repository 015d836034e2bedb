#include "gl/shadow_maps.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "core/error.h"
#include "gl/shader.h"

namespace nf::gl {

ShadowFrustum shadow_frustum_for(const NfLuminaire& lum, double max_half_angle_deg, double margin) {
  if (!(lum.delta > 0.0f)) fail("shadow maps: luminaire delta must be > 0");
  const double cells_x = lum.count_x + lum.support - 1, cells_y = lum.count_y + lum.support - 1;
  const double u0x = lum.basis_origin_x, u1x = lum.basis_origin_x + cells_x * lum.cell_x;
  const double u0y = lum.basis_origin_y, u1y = lum.basis_origin_y + cells_y * lum.cell_y;
  const double s0x = lum.image_origin_x, s1x = lum.image_origin_x + lum.image_size_x;
  const double s0y = lum.image_origin_y, s1y = lum.image_origin_y + lum.image_size_y;
  const double d = lum.delta;
  const double lim = std::tan(std::clamp(max_half_angle_deg, 1.0, 89.0) * 3.14159265358979323846 / 180.0);
  const auto range = [&](double lo, double hi, double& out_lo, double& out_hi) {
    const double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo) * (1.0 + margin) + 1e-6;
    out_lo = std::clamp(c - h, -lim, lim);
    out_hi = std::clamp(c + h, -lim, lim);
    if (out_hi - out_lo < 1e-3) {  // all emission beyond the limit: keep a sliver at the edge
      out_lo = std::min(out_lo, lim - 1e-3);
      out_hi = out_lo + 1e-3;
    }
  };
  ShadowFrustum f;
  range((s0x - u1x) / d, (s1x - u0x) / d, f.left, f.right);
  range((s0y - u1y) / d, (s1y - u0y) / d, f.bottom, f.top);
  return f;
}

ShadowMapSpec make_shadow_map_spec(const NfLuminaire& lum, const std::vector<glm::dvec3>& ref_lights,
                                   const glm::dmat4& to_world, int size) {
  ShadowMapSpec s;
  s.cells_x = lum.count_x + lum.support - 1;
  s.cells_y = lum.count_y + lum.support - 1;
  s.lights = ref_lights;
  s.to_world = to_world;
  s.size = size;
  s.frustum = shadow_frustum_for(lum);
  return s;
}

ShadowMapSpec single_position_spec(ShadowMapSpec full) {
  glm::dvec3 mean(0.0);
  for (const auto& l : full.lights) mean += l;
  if (!full.lights.empty()) mean /= static_cast<double>(full.lights.size());
  for (auto& l : full.lights) l = mean;
  full.map_of_cell.assign(full.lights.size(), 0);
  return full;
}

bool box_in_shadow_frusta(const ShadowMapSpec& spec, const glm::dvec3& lo, const glm::dvec3& hi, bool grow) {
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z || spec.lights.empty()) return false;  // empty box
  // The box in the luminaire frame (the local bounds of its 8 corners contain it).
  const glm::dmat4 to_local = glm::inverse(spec.to_world);
  glm::dvec3 a(std::numeric_limits<double>::max()), b(-std::numeric_limits<double>::max());
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 c((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    const glm::dvec3 l(to_local * glm::dvec4(c, 1.0));
    a = glm::min(a, l);
    b = glm::max(b, l);
  }
  const auto& f = spec.frustum;
  double lz_min = std::numeric_limits<double>::max();
  for (const auto& l : spec.lights) lz_min = std::min(lz_min, l.z);
  // The pass moves p by at most normal_texels * texel(z) = normal_texels * z * max(r - l, t - b) /
  // size along the unit normal; grow the box by that at its farthest z, plus a float margin
  // (the pass computes in float: 1e-4 relative to the box's size and distance).
  const double extent = glm::length(b - a) + glm::length(0.5 * (a + b));
  const double texel_per_z = std::max(f.right - f.left, f.top - f.bottom) / spec.size;
  const double g = (grow ? spec.bias.normal_texels * texel_per_z * std::max(0.0, b.z - lz_min) : 0.0) + 1e-4 * extent;
  a -= g;
  b += g;
  for (const auto& light : spec.lights) {
    const glm::dvec3 lo_q = a - light, hi_q = b - light;
    if (hi_q.z <= f.near) continue;  // behind the near plane: q0.z <= near or q.z <= near, lit
    // Outside one side for every z > 0 in the box: the linear x - k z (or y - k z) keeps its sign
    // over the box (extremes at corners). Points with z <= near are lit anyway.
    const auto min_lin = [&](double x0, double x1, double k) {
      return std::min({x0 - k * lo_q.z, x0 - k * hi_q.z, x1 - k * lo_q.z, x1 - k * hi_q.z});
    };
    const auto max_lin = [&](double x0, double x1, double k) {
      return std::max({x0 - k * lo_q.z, x0 - k * hi_q.z, x1 - k * lo_q.z, x1 - k * hi_q.z});
    };
    const bool outside = min_lin(lo_q.x, hi_q.x, f.right) >= 0.0 || max_lin(lo_q.x, hi_q.x, f.left) < 0.0 ||
                         min_lin(lo_q.y, hi_q.y, f.top) >= 0.0 || max_lin(lo_q.y, hi_q.y, f.bottom) < 0.0;
    if (!outside) return true;
  }
  return false;
}

std::size_t ShadowMaps::bytes(const ShadowMapSpec& spec) {
  int maps = spec.cells_x * spec.cells_y;
  if (!spec.map_of_cell.empty()) maps = *std::max_element(spec.map_of_cell.begin(), spec.map_of_cell.end()) + 1;
  const std::size_t texels = static_cast<std::size_t>(spec.size) * static_cast<std::size_t>(spec.size);
  return texels * 4 * static_cast<std::size_t>(maps) + texels * 4 + spec.lights.size() * 16;
}

ShadowMaps::ShadowMaps(ShadowMapSpec spec) : spec_(std::move(spec)) {
  const int n = cells();
  if (spec_.cells_x <= 0 || spec_.cells_y <= 0 || static_cast<std::size_t>(n) != spec_.lights.size())
    fail(fmt::format("shadow maps: {}x{} cells but {} reference lights", spec_.cells_x, spec_.cells_y,
                     spec_.lights.size()));
  if (spec_.size < 1 || spec_.size > 16384) fail(fmt::format("shadow maps: size {} out of range", spec_.size));
  const auto& f = spec_.frustum;
  if (!(f.right > f.left) || !(f.top > f.bottom) || !(f.near > 0.0)) fail("shadow maps: invalid frustum");
  if (spec_.map_of_cell.empty()) {
    map_lights_ = spec_.lights;
  } else {
    if (spec_.map_of_cell.size() != spec_.lights.size())
      fail(fmt::format("shadow maps: {} map indices for {} cells", spec_.map_of_cell.size(), n));
    const int maps = *std::max_element(spec_.map_of_cell.begin(), spec_.map_of_cell.end()) + 1;
    map_lights_.assign(static_cast<std::size_t>(std::max(maps, 0)), glm::dvec3(0.0));
    std::vector<bool> seen(map_lights_.size(), false);
    for (int c = 0; c < n; ++c) {
      const int m = spec_.map_of_cell[static_cast<std::size_t>(c)];
      if (m < 0) fail(fmt::format("shadow maps: cell {} has map index {}", c, m));
      const auto& l = spec_.lights[static_cast<std::size_t>(c)];
      if (seen[static_cast<std::size_t>(m)] && map_lights_[static_cast<std::size_t>(m)] != l)
        fail(fmt::format("shadow maps: the cells of map {} have different lights", m));
      map_lights_[static_cast<std::size_t>(m)] = l;
      seen[static_cast<std::size_t>(m)] = true;
    }
  }
  // The maps live in up to kMaxMapBuffers storage buffers, each within the block-size limit
  // (128 MiB on llvmpipe).
  GLint64 max_block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  const std::size_t map_bytes = static_cast<std::size_t>(spec_.size) * spec_.size * sizeof(float);
  maps_per_buffer_ = static_cast<int>(std::min<std::int64_t>(max_block / static_cast<std::int64_t>(map_bytes), maps()));
  if (maps_per_buffer_ < 1 || (maps() + maps_per_buffer_ - 1) / maps_per_buffer_ > kMaxMapBuffers)
    fail(
        fmt::format("shadow maps: {} maps of {}^2 floats exceed {} storage buffers of {} bytes (GL limit); use "
                    "smaller maps",
                    maps(), spec_.size, kMaxMapBuffers, max_block));

  // Per cell: its light (xyz) and its map's index (w), which the visibility passes read.
  std::vector<float> lights(static_cast<std::size_t>(n) * 4, 0.0f);
  for (int c = 0; c < n; ++c) {
    for (int k = 0; k < 3; ++k)
      lights[static_cast<std::size_t>(c) * 4 + static_cast<std::size_t>(k)] =
          static_cast<float>(spec_.lights[static_cast<std::size_t>(c)][k]);
    lights[static_cast<std::size_t>(c) * 4 + 3] =
        static_cast<float>(spec_.map_of_cell.empty() ? c : spec_.map_of_cell[static_cast<std::size_t>(c)]);
  }
  glCreateBuffers(1, &lights_ssbo_);
  glNamedBufferStorage(lights_ssbo_, static_cast<GLsizeiptr>(lights.size() * sizeof(float)), lights.data(), 0);

  depth_program_ = build_program("shadow_depth.vert.glsl", "shadow_depth.frag.glsl");
  vis_program_ = build_compute_program("visibility.comp.glsl");
}

void ShadowMaps::allocate() {
  if (allocated()) return;
  const int n = maps();
  const std::size_t map_bytes = static_cast<std::size_t>(spec_.size) * spec_.size * sizeof(float);
  // One depth target, reused for every map; each finished map is copied into one storage
  // buffer (maps x size^2 floats) that the visibility pass indexes directly (faster than a
  // texture-array fetch on llvmpipe, and half the memory of target array + copy).
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, spec_.size, spec_.size);
  glCreateFramebuffers(1, &fbo_);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  glNamedFramebufferDrawBuffer(fbo_, GL_NONE);
  glNamedFramebufferReadBuffer(fbo_, GL_NONE);
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) fail(fmt::format("shadow-map framebuffer incomplete: 0x{:x}", status));
  maps_bytes_ = map_bytes * static_cast<std::size_t>(n);
  for (int first = 0; first < n; first += maps_per_buffer_) {
    GLuint b = 0;
    glCreateBuffers(1, &b);
    glNamedBufferStorage(
        b, static_cast<GLsizeiptr>(map_bytes * static_cast<std::size_t>(std::min(maps_per_buffer_, n - first))),
        nullptr, 0);
    maps_ssbo_.push_back(b);
  }
}

ShadowMaps::~ShadowMaps() {
  if (depth_) glDeleteTextures(1, &depth_);
  for (auto b : maps_ssbo_) glDeleteBuffers(1, &b);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (lights_ssbo_) glDeleteBuffers(1, &lights_ssbo_);
  if (vis_ssbo_) glDeleteBuffers(1, &vis_ssbo_);
  if (depth_program_) glDeleteProgram(depth_program_);
  if (vis_program_) glDeleteProgram(vis_program_);
}

glm::dmat4 ShadowMaps::light_clip(int map) const {
  const auto& f = spec_.frustum;
  const glm::dmat4 to_light =
      glm::translate(glm::dmat4(1.0), -map_lights_[static_cast<std::size_t>(map)]) * glm::inverse(spec_.to_world);
  return reversed_z_frustum(f.left, f.right, f.bottom, f.top, f.near) * to_light;
}

void ShadowMaps::render(const SceneGpu& scene) {
  allocate();
  ReversedZScope depth_state;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, spec_.size, spec_.size);
  glUseProgram(depth_program_);
  const std::size_t map_bytes = static_cast<std::size_t>(spec_.size) * spec_.size * sizeof(float);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  for (int c = 0; c < maps(); ++c) {
    glBindBuffer(GL_PIXEL_PACK_BUFFER, maps_ssbo_[static_cast<std::size_t>(c / maps_per_buffer_)]);
    glUseProgram(depth_program_);
    glClear(GL_DEPTH_BUFFER_BIT);
    scene.draw(light_clip(c), false, true);
    // GPU-side copy into the maps buffer at layer c (rows bottom to top, as GL stores them).
    glGetTextureImage(depth_, 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(map_bytes),
                      reinterpret_cast<void*>(static_cast<std::size_t>(c % maps_per_buffer_) * map_bytes));
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

std::vector<std::uint32_t> ShadowMaps::visibility(const GBuffer& gbuffer) {
  if (!allocated()) fail("shadow maps: visibility() before render()");
  const int w = gbuffer.width(), h = gbuffer.height();
  const std::size_t words = static_cast<std::size_t>(w) * h * static_cast<std::size_t>(words_per_pixel());
  const std::size_t bytes = std::max<std::size_t>(words * sizeof(std::uint32_t), 4);
  if (bytes != vis_bytes_) {
    if (vis_ssbo_) glDeleteBuffers(1, &vis_ssbo_);
    glCreateBuffers(1, &vis_ssbo_);
    glNamedBufferStorage(vis_ssbo_, static_cast<GLsizeiptr>(bytes), nullptr, GL_MAP_READ_BIT);
    vis_bytes_ = bytes;
  }
  const auto& f = spec_.frustum;
  const glm::mat4 world_to_local(glm::inverse(spec_.to_world));
  glUseProgram(vis_program_);
  glBindTextureUnit(0, gbuffer.position_texture());
  glBindTextureUnit(1, gbuffer.normal_texture());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lights_ssbo_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, vis_ssbo_);
  for (int k = 0; k < kMaxMapBuffers; ++k)  // unused slots repeat the first buffer
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(2 + k),
                     maps_ssbo_[static_cast<std::size_t>(k) < maps_ssbo_.size() ? static_cast<std::size_t>(k) : 0]);
  glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(world_to_local));
  glUniform2i(1, w, h);
  glUniform1i(2, cells());
  glUniform1i(3, words_per_pixel());
  glUniform1i(4, spec_.size);
  glUniform4f(5, static_cast<float>(f.left), static_cast<float>(f.right), static_cast<float>(f.bottom),
              static_cast<float>(f.top));
  glUniform1f(6, static_cast<float>(f.near));
  glUniform1i(8, maps_per_buffer_);
  glUniform3f(7, static_cast<float>(spec_.bias.constant), static_cast<float>(spec_.bias.depth_texels),
              static_cast<float>(spec_.bias.normal_texels));
  const GLuint groups = static_cast<GLuint>((static_cast<std::size_t>(w) * h + 63) / 64);
  glDispatchCompute(groups, static_cast<GLuint>(words_per_pixel()), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<std::uint32_t> out(words);
  if (words) glGetNamedBufferSubData(vis_ssbo_, 0, static_cast<GLsizeiptr>(words * sizeof(std::uint32_t)), out.data());
  glUseProgram(0);
  return out;
}

std::vector<float> ShadowMaps::read_depth(int cell) const {
  if (cell < 0 || cell >= cells()) fail(fmt::format("shadow maps: cell {} out of range", cell));
  if (!allocated()) fail("shadow maps: read_depth() before render()");
  const int s = spec_.size;
  if (!spec_.map_of_cell.empty()) cell = spec_.map_of_cell[static_cast<std::size_t>(cell)];
  std::vector<float> raw(static_cast<std::size_t>(s) * s);
  glGetNamedBufferSubData(
      maps_ssbo_[static_cast<std::size_t>(cell / maps_per_buffer_)],
      static_cast<GLintptr>(static_cast<std::size_t>(cell % maps_per_buffer_) * raw.size() * sizeof(float)),
      static_cast<GLsizeiptr>(raw.size() * sizeof(float)), raw.data());
  std::vector<float> out(raw.size());
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      const float d = raw[static_cast<std::size_t>(s - 1 - y) * s + x];
      out[static_cast<std::size_t>(y) * s + x] =
          d > 0.0f ? static_cast<float>(spec_.frustum.near / d) : std::numeric_limits<float>::infinity();
    }
  return out;
}

std::vector<float> ShadowMaps::read_maps() const {
  const std::size_t texels = static_cast<std::size_t>(spec_.size) * static_cast<std::size_t>(spec_.size);
  std::vector<float> out(texels * static_cast<std::size_t>(maps()));
  if (!allocated()) fail("shadow maps: read_maps() before render()");
  for (int first = 0; first < maps(); first += maps_per_buffer_) {
    const std::size_t n = static_cast<std::size_t>(std::min(maps_per_buffer_, maps() - first));
    glGetNamedBufferSubData(maps_ssbo_[static_cast<std::size_t>(first / maps_per_buffer_)], 0,
                            static_cast<GLsizeiptr>(n * texels * sizeof(float)),
                            out.data() + static_cast<std::size_t>(first) * texels);
  }
  return out;
}

std::vector<MemoryItem> ShadowMaps::memory() const {
  std::vector<MemoryItem> m{{"shadow reference lights", static_cast<std::size_t>(cells()) * 16}};
  if (allocated()) {
    m.push_back({fmt::format("shadow maps ({} x {}^2 float)", maps(), spec_.size), maps_bytes_});
    m.push_back({fmt::format("shadow depth target ({}^2 D32F)", spec_.size),
                 static_cast<std::size_t>(spec_.size) * spec_.size * 4});
  }
  if (vis_bytes_) m.push_back({"visibility bitmask", vis_bytes_});
  return m;
}

}  // namespace nf::gl
