#include "app/photometric_images.h"

#include <cmath>

#include "core/color.h"

namespace nf::app {

constexpr double kPi = 3.14159265358979323846;

Image luminance_channel(const Image& rgb) {
  Image y(rgb.width, rgb.height, 1);
  const std::size_t n = static_cast<std::size_t>(rgb.width) * static_cast<std::size_t>(rgb.height);
  const std::size_t c = static_cast<std::size_t>(rgb.channels);
  for (std::size_t p = 0; p < n; ++p) {
    const float* px = rgb.pixels.data() + p * c;
    const double v = c >= 3 ? color::kLumR * static_cast<double>(px[0]) + color::kLumG * static_cast<double>(px[1]) +
                                  color::kLumB * static_cast<double>(px[2])
                            : px[0];
    y.pixels[p] = std::isfinite(v) ? static_cast<float>(v) : 0.0f;
  }
  return y;
}

scene::Scene illuminance_scene(scene::Scene scene) {
  for (auto& m : scene.geometry.materials) {
    m.kind = scene::MaterialKind::lambert;
    m.base_color = glm::vec3(1.0f);  // rho = 1: L = E / pi
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.base_color_texture = -1;
    m.metallic_roughness_texture = -1;
    m.kurt_lobes.clear();
  }
  scene.environment.reset();
  scene.local_environments.clear();
  scene.render.indirect = "none";
  return scene;
}

Image illuminance_from_white(const Image& white, const std::vector<render::PixelKind>& kinds) {
  Image e = luminance_channel(white);
  for (std::size_t p = 0; p < e.pixels.size(); ++p) {
    const bool surface = p < kinds.size() && kinds[p] == render::PixelKind::surface;
    e.pixels[p] = surface ? static_cast<float>(kPi * e.pixels[p]) : 0.0f;
  }
  return e;
}

Image render_illuminance(const scene::Scene& scene, int frames, const render::RendererOptions& options) {
  render::Renderer r(illuminance_scene(scene), options);
  for (int f = 0; f < frames; ++f) r.render_frame();
  return illuminance_from_white(r.accumulated(), r.pixel_kinds());
}

}  // namespace nf::app
