#include "app/viewer_readout.h"

#include <fmt/format.h>

#include "app/photometric_images.h"

namespace nf::app {

std::string PixelReadout::text(const ImageUnits& units) const {
  if (!inside) return "outside the image";
  const std::string lu = units.radiance.empty() ? "" : " " + units.radiance;
  const std::string eu = units.illuminance.empty() ? "" : " " + units.illuminance;
  std::string t = fmt::format("({}, {}) L {:.4g}{}", x, y, luminance, lu);
  if (kind == render::PixelKind::background) return t + " (background)";
  if (kind == render::PixelKind::luminaire) return t + " (luminaire)";
  return t + (illuminance ? fmt::format(" | E {:.4g}{}", *illuminance, eu) : std::string(" | E not computed"));
}

ViewerReadout::View ViewerReadout::view_of(const render::Renderer& r) {
  View v{r.camera(), {}, {}};
  for (std::size_t i = 0; i < r.luminaire_count(); ++i) {
    v.lums.push_back(r.luminaire_transform(i));
    v.intensities.push_back(r.luminaire_intensity(i));
  }
  return v;
}

bool ViewerReadout::same(const View& a, const View& b) {
  const scene::Camera &p = a.camera, &q = b.camera;
  return p.position == q.position && p.target == q.target && p.up == q.up && p.fov_y_deg == q.fov_y_deg &&
         p.width == q.width && p.height == q.height && a.lums == b.lums && a.intensities == b.intensities;
}

bool ViewerReadout::has_illuminance(const render::Renderer& r) const {
  return illuminance_view_ && same(*illuminance_view_, view_of(r));
}

PixelReadout ViewerReadout::at(const render::Renderer& r, int x, int y) {
  PixelReadout o;
  const scene::Camera& c = r.camera();
  if (x < 0 || y < 0 || x >= c.width || y >= c.height) return o;
  if (luminance_stale_ || luminance_.width != c.width || luminance_.height != c.height) {
    luminance_ = luminance_channel(r.accumulated());
    luminance_stale_ = false;
  }
  o.inside = true;
  o.x = x;
  o.y = y;
  const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(c.width) + static_cast<std::size_t>(x);
  o.kind = p < r.pixel_kinds().size() ? r.pixel_kinds()[p] : render::PixelKind::background;
  o.luminance = luminance_.pixels[p];
  if (o.kind == render::PixelKind::surface && has_illuminance(r) && illuminance_.width == c.width)
    o.illuminance = illuminance_.pixels[p];
  return o;
}

void ViewerReadout::compute_illuminance(render::Renderer& r, gl::Context& context, int frames) {
  scene::Scene s = r.scene();
  s.camera = r.camera();
  for (std::size_t i = 0; i < r.luminaire_count() && i < s.luminaires.size(); ++i) {
    s.luminaires[i].to_world = r.luminaire_transform(i);
    s.luminaires[i].intensity = r.luminaire_intensity(i);
  }
  s.render = r.settings().declared;
  render::RendererOptions o;
  o.runtime = &r.runtime();
  o.context = &context;
  illuminance_ = render_illuminance(s, frames, o);
  illuminance_view_ = view_of(r);
}

}  // namespace nf::app
