#include "gl/tonemap.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "gl/shader.h"

namespace nf::gl {

namespace {
constexpr int kMeanGroupSize = 256;  // must match tonemap_mean.comp.glsl
}

Tonemapper::Tonemapper(int width, int height) : out_(width, height, {GL_RGBA32F}, false) {
  glCreateTextures(GL_TEXTURE_2D, 1, &input_);
  glTextureStorage2D(input_, 1, GL_RGBA32F, width, height);
  glTextureParameteri(input_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(input_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  groups_ = static_cast<int>(std::clamp<std::size_t>((n + 16 * kMeanGroupSize - 1) / (16 * kMeanGroupSize), 1, 1024));
  glCreateBuffers(1, &partial_ssbo_);
  glNamedBufferStorage(partial_ssbo_, static_cast<GLsizeiptr>(groups_) * 2 * sizeof(float), nullptr, GL_MAP_READ_BIT);
  glCreateVertexArrays(1, &vao_);
  mean_program_ = build_compute_program("tonemap_mean.comp.glsl");
  map_program_ = build_program("fullscreen.vert.glsl", "tonemap.frag.glsl");
}

Tonemapper::~Tonemapper() {
  if (input_) glDeleteTextures(1, &input_);
  if (partial_ssbo_) glDeleteBuffers(1, &partial_ssbo_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (mean_program_) glDeleteProgram(mean_program_);
  if (map_program_) glDeleteProgram(map_program_);
}

void Tonemapper::upload(const Image& hdr, const std::vector<std::uint8_t>& valid) {
  if (hdr.width != width() || hdr.height != height())
    fail(fmt::format("tone mapping: frame is {}x{}, tone mapper {}x{}", hdr.width, hdr.height, width(), height()));
  if (hdr.channels != 1 && hdr.channels < 3) fail(fmt::format("tone mapping: {} channels", hdr.channels));
  const std::size_t n = static_cast<std::size_t>(width()) * height();
  if (!valid.empty() && valid.size() != n) fail("tone mapping: mask size differs from the frame");
  std::vector<float> rgba(n * 4);
  const auto ch = static_cast<std::size_t>(hdr.channels);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &hdr.pixels[i * ch];
    for (std::size_t c = 0; c < 3; ++c) rgba[i * 4 + c] = hdr.channels == 1 ? p[0] : p[c];
    rgba[i * 4 + 3] = valid.empty() || valid[i] ? 1.0f : 0.0f;
  }
  upload_rgba(rgba.data());
}

void Tonemapper::upload_rgba(const float* rgba) {
  const int w = width(), h = height();
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Row y of the image goes to GL row h - 1 - y (GL rows run bottom to top).
  for (int y = 0; y < h; ++y)
    glTextureSubImage2D(input_, 0, 0, h - 1 - y, w, 1, GL_RGBA, GL_FLOAT, rgba + static_cast<std::size_t>(y) * w * 4);
}

void Tonemapper::show_rgba8(const std::uint8_t* rgba8) {
  // As floats (bytes / 255) in GL row order (bottom to top): the RGBA32F texture's fast upload
  // path (a byte upload makes Mesa convert texel by texel).
  const auto w = static_cast<std::size_t>(width()), h = static_cast<std::size_t>(height());
  std::vector<float> rgba(4 * w * h);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* src = rgba8 + 4 * w * y;
    float* dst = rgba.data() + 4 * w * (h - 1 - y);
    for (std::size_t i = 0; i < 4 * w; ++i) dst[i] = static_cast<float>(src[i]) * (1.0f / 255.0f);
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(out_.texture(0), 0, 0, 0, width(), height(), GL_RGBA, GL_FLOAT, rgba.data());
}

double Tonemapper::mean_luminance() {
  glUseProgram(mean_program_);
  glBindTextureUnit(0, input_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, partial_ssbo_);
  glUniform2i(0, width(), height());
  glDispatchCompute(static_cast<GLuint>(groups_), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> partial(static_cast<std::size_t>(groups_) * 2);
  glGetNamedBufferSubData(partial_ssbo_, 0, static_cast<GLsizeiptr>(partial.size() * sizeof(float)), partial.data());
  glUseProgram(0);
  double sum = 0.0, count = 0.0;
  for (int g = 0; g < groups_; ++g) {
    sum += partial[static_cast<std::size_t>(2 * g)];
    count += partial[static_cast<std::size_t>(2 * g + 1)];
  }
  return count > 0.0 ? sum / count : 0.0;
}

double Tonemapper::render(const TonemapParams& params, double mean) {
  if (!(params.exposure > 0.0) || !(params.gamma > 0.0))
    fail(fmt::format("tone mapping: exposure ({}) and gamma ({}) must be > 0", params.exposure, params.gamma));
  if (mean < 0.0) mean = mean_luminance();
  const float k = mean > 0.0 && std::isfinite(mean) ? static_cast<float>(params.exposure / mean) : 0.0f;
  out_.bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(map_program_);
  glBindTextureUnit(0, input_);
  glUniform1f(0, k);
  glUniform1f(1, static_cast<float>(1.0 / params.gamma));
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return mean;
}

void Tonemapper::present(unsigned target, int x, int y, int width, int height) const {
  if (width <= 0 || height <= 0) return;
  const double scale =
      std::min(static_cast<double>(width) / this->width(), static_cast<double>(height) / this->height());
  const int w = static_cast<int>(this->width() * scale), h = static_cast<int>(this->height() * scale);
  const int x0 = x + (width - w) / 2, y0 = y + (height - h) / 2;
  const float black[4] = {0, 0, 0, 1};
  glClearNamedFramebufferfv(target, GL_COLOR, 0, black);
  glNamedFramebufferReadBuffer(out_.id(), GL_COLOR_ATTACHMENT0);
  glBlitNamedFramebuffer(out_.id(), target, 0, 0, this->width(), this->height(), x0, y0, x0 + w, y0 + h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

Image Tonemapper::read() const { return out_.read(0, 3); }

std::vector<MemoryItem> Tonemapper::memory() const {
  const std::size_t px = static_cast<std::size_t>(width()) * height();
  return {{"tonemap input (RGBA32F)", px * 16},
          {"tonemap output (RGBA32F)", px * 16},
          {"tonemap partial sums", static_cast<std::size_t>(groups_) * 8}};
}

}  // namespace nf::gl
