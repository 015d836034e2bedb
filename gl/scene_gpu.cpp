#include "gl/scene_gpu.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"

namespace nf::gl {

std::size_t total_bytes(const std::vector<MemoryItem>& items) {
  std::size_t n = 0;
  for (const auto& i : items) n += i.bytes;
  return n;
}

glm::dmat4 reversed_z_frustum(double l, double r, double b, double t, double near) {
  if (!(r > l) || !(t > b) || !(near > 0.0))
    fail(fmt::format("projection: invalid frustum l={} r={} b={} t={} near={}", l, r, b, t, near));
  // Rows: x_c = (2x - (r+l) z)/(r-l), y_c = (2y - (t+b) z)/(t-b), z_c = near, w_c = z.
  glm::dmat4 m(0.0);  // column-major: m[col][row]
  m[0][0] = 2.0 / (r - l);
  m[2][0] = -(r + l) / (r - l);
  m[1][1] = 2.0 / (t - b);
  m[2][1] = -(t + b) / (t - b);
  m[3][2] = near;
  m[2][3] = 1.0;
  return m;
}

glm::dmat4 camera_view(const scene::Camera& c) {
  const glm::dvec3 f = c.forward(), r = c.right(), u = c.true_up();
  glm::dmat4 v(1.0);
  for (int i = 0; i < 3; ++i) {
    v[i][0] = r[i];
    v[i][1] = u[i];
    v[i][2] = f[i];
  }
  v[3][0] = -glm::dot(r, c.position);
  v[3][1] = -glm::dot(u, c.position);
  v[3][2] = -glm::dot(f, c.position);
  return v;
}

glm::dmat4 camera_projection(const scene::Camera& c) {
  const double ty = c.tan_half_fov_y(), tx = ty * c.aspect();
  return reversed_z_frustum(-tx, tx, -ty, ty, c.near);
}

ReversedZScope::ReversedZScope() {
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glClearDepth(0.0);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
}

ReversedZScope::~ReversedZScope() {
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glDepthFunc(GL_LESS);
  glClearDepth(1.0);
  glDisable(GL_DEPTH_TEST);
  glFrontFace(GL_CCW);
}

namespace {

int mip_levels(int w, int h) {
  int levels = 1;
  while ((std::max(w, h) >> levels) > 0) ++levels;
  return levels;
}

GLuint upload_texture(const scene::Texture& t, bool srgb, std::size_t& bytes) {
  GLuint tex = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  const int levels = mip_levels(t.width, t.height);
  glTextureStorage2D(tex, levels, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, t.width, t.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Rows in file order: row 0 (top of the image) at t = 0, which is glTF's uv convention.
  glTextureSubImage2D(tex, 0, 0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, t.rgba8.data());
  glGenerateTextureMipmap(tex);
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_REPEAT);
  bytes += t.rgba8.size() * 4 / 3;  // with the mip chain
  return tex;
}

}  // namespace

SceneGpu::SceneGpu(const scene::Geometry& g) : materials_(g.materials) {
  // One interleaved vertex buffer (position, normal, uv: 8 floats) and one index buffer.
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<int> base_vertex(g.meshes.size());
  std::vector<std::size_t> first_index(g.meshes.size());
  for (std::size_t m = 0; m < g.meshes.size(); ++m) {
    const auto& mesh = g.meshes[m];
    if (mesh.normals.size() != mesh.positions.size() || (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()))
      fail(fmt::format("mesh '{}': attribute counts differ", mesh.name));
    base_vertex[m] = static_cast<int>(vertices.size() / 8);
    first_index[m] = indices.size();
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec2 uv = mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[v];
      vertices.insert(vertices.end(), {mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z, mesh.normals[v].x,
                                       mesh.normals[v].y, mesh.normals[v].z, uv.x, uv.y});
    }
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
  }
  vertex_bytes_ = vertices.size() * sizeof(float);
  index_bytes_ = indices.size() * sizeof(std::uint32_t);

  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(1, &vbo_);
  glCreateBuffers(1, &ibo_);
  glNamedBufferStorage(vbo_, static_cast<GLsizeiptr>(std::max<std::size_t>(vertex_bytes_, 4)),
                       vertices.empty() ? nullptr : vertices.data(), 0);
  glNamedBufferStorage(ibo_, static_cast<GLsizeiptr>(std::max<std::size_t>(index_bytes_, 4)),
                       indices.empty() ? nullptr : indices.data(), 0);
  glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, 8 * sizeof(float));
  glVertexArrayElementBuffer(vao_, ibo_);
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao_, a);
    glVertexArrayAttribFormat(vao_, a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
    glVertexArrayAttribBinding(vao_, a, 0);
  }

  srgb_tex_.assign(g.textures.size(), 0);
  linear_tex_.assign(g.textures.size(), 0);
  upload_textures(g);
  glCreateTextures(GL_TEXTURE_2D, 1, &white_);
  glTextureStorage2D(white_, 1, GL_RGBA8, 1, 1);
  const std::uint8_t white[4] = {255, 255, 255, 255};
  glTextureSubImage2D(white_, 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);

  for (const auto& inst : g.instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(g.meshes.size()))
      fail(fmt::format("instance of object {}: mesh {} out of range", inst.object, inst.mesh));
    if (inst.material < 0 || inst.material >= static_cast<int>(g.materials.size()))
      fail(fmt::format("instance of object {}: material {} out of range", inst.object, inst.material));
    const auto& mesh = g.meshes[static_cast<std::size_t>(inst.mesh)];
    DrawItem d;
    d.base_vertex = base_vertex[static_cast<std::size_t>(inst.mesh)];
    d.first_index = first_index[static_cast<std::size_t>(inst.mesh)];
    d.index_count = static_cast<int>(mesh.indices.size());
    d.model = inst.to_world;
    const glm::dmat3 m3(inst.to_world);
    d.normal_matrix = glm::mat3(glm::transpose(glm::inverse(m3)));
    d.mirrored = glm::determinant(m3) < 0.0;
    d.material = inst.material;
    d.casts = inst.casts_shadows;
    triangles_ += mesh.triangle_count();
    if (d.index_count > 0) draws_.push_back(d);
  }
}

// Textures: sRGB for base colour, linear for metallic-roughness; only those in use, once each.
void SceneGpu::upload_textures(const scene::Geometry& g) {
  for (const auto& mat : g.materials) {
    const auto check = [&](int t) {
      if (t >= static_cast<int>(g.textures.size()))
        fail(fmt::format("material '{}': texture {} out of range", mat.name, t));
    };
    check(mat.base_color_texture);
    check(mat.metallic_roughness_texture);
    if (mat.base_color_texture >= 0 && !srgb_tex_[static_cast<std::size_t>(mat.base_color_texture)])
      srgb_tex_[static_cast<std::size_t>(mat.base_color_texture)] =
          upload_texture(g.textures[static_cast<std::size_t>(mat.base_color_texture)], true, texture_bytes_);
    if (mat.metallic_roughness_texture >= 0 && !linear_tex_[static_cast<std::size_t>(mat.metallic_roughness_texture)])
      linear_tex_[static_cast<std::size_t>(mat.metallic_roughness_texture)] =
          upload_texture(g.textures[static_cast<std::size_t>(mat.metallic_roughness_texture)], false, texture_bytes_);
  }
}

void SceneGpu::set_materials(const scene::Geometry& g) {
  if (g.materials.size() != materials_.size())
    fail(fmt::format("set_materials: {} materials for a scene with {}", g.materials.size(), materials_.size()));
  if (g.textures.size() != srgb_tex_.size()) fail("set_materials: the scene's textures changed");
  upload_textures(g);
  materials_ = g.materials;
}

SceneGpu::~SceneGpu() {
  for (auto t : srgb_tex_)
    if (t) glDeleteTextures(1, &t);
  for (auto t : linear_tex_)
    if (t) glDeleteTextures(1, &t);
  if (white_) glDeleteTextures(1, &white_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (ibo_) glDeleteBuffers(1, &ibo_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void SceneGpu::draw(const glm::dmat4& pre, bool materials, bool casters_only) const {
  glBindVertexArray(vao_);
  const glm::mat4 pre_f(pre);
  glUniformMatrix4fv(1, 1, GL_FALSE, glm::value_ptr(pre_f));
  for (const auto& d : draws_) {
    if (casters_only && !d.casts) continue;
    const glm::mat4 model(d.model);
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(model));
    if (materials) {
      glUniformMatrix3fv(2, 1, GL_FALSE, glm::value_ptr(d.normal_matrix));
      const auto& mat = materials_[static_cast<std::size_t>(d.material)];
      if (mat.kind == scene::MaterialKind::kurt) {
        // kurt: the G-buffer's base colour carries the world tangent (gl/gbuffer.h)
        const glm::vec3 t = glm::mat3(model) * mat.tangent;
        glUniform3f(3, t.x, t.y, t.z);
      } else {
        glUniform3f(3, mat.base_color.r, mat.base_color.g, mat.base_color.b);
      }
      glUniform1f(4, mat.kind == scene::MaterialKind::ggx ? mat.metallic : 0.0f);
      glUniform1f(5, mat.kind == scene::MaterialKind::ggx ? mat.roughness : 1.0f);
      glUniform1f(6, static_cast<float>(d.material + 1));
      glBindTextureUnit(
          0, mat.base_color_texture >= 0 ? srgb_tex_[static_cast<std::size_t>(mat.base_color_texture)] : white_);
      glBindTextureUnit(1, mat.metallic_roughness_texture >= 0
                               ? linear_tex_[static_cast<std::size_t>(mat.metallic_roughness_texture)]
                               : white_);
    }
    glFrontFace(d.mirrored ? GL_CW : GL_CCW);
    glDrawElementsBaseVertex(GL_TRIANGLES, d.index_count, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(d.first_index * sizeof(std::uint32_t)), d.base_vertex);
  }
  glFrontFace(GL_CCW);
  glBindVertexArray(0);
}

std::vector<MemoryItem> SceneGpu::memory() const {
  return {{"scene vertices", vertex_bytes_}, {"scene indices", index_bytes_}, {"scene textures", texture_bytes_}};
}

}  // namespace nf::gl
