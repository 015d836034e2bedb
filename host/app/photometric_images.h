#pragma once
// Luminance and illuminance images of a rendered view (docs/photometry.md, "Luminance and
// illuminance images"; units: app/image_units.h).
//
// Illuminance by the frame's own kernels. A Lambertian surface of albedo rho = 1 reflects
//   L = integral over the hemisphere of (rho / pi) L_i(w) cos(theta) dw = E / pi,
// so rendering the view with every material replaced by white Lambert (albedo 1, no texture),
// direct light only, gives E = pi L per channel, and with the sources' colours scaled to unit
// luminance (docs/photometry.md, "Colour") E_v = pi Y(L) in lx for a photometric scene. The
// estimators are those of the beauty render (light-field sampling, the far-field lights' closed
// form, the frame's visibility), so the illuminance has the same noise as a white floor would.
// Left out: the environment (its units are the map's) and indirect light (one bounce), i.e. E is
// the direct illuminance from the luminaires and far-field lights, as `rtrace -I -ab 0` gives it.
#include <vector>

#include "core/image.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace nf::app {

// Y = 0.2126 R + 0.7152 G + 0.0722 B per pixel (1 channel); non-finite values give 0.
Image luminance_channel(const Image& rgb);

// The scene of the illuminance pass: every material white Lambert (albedo 1, no textures), no
// environment or local environment maps, indirect light off. Everything else (camera, geometry,
// luminaires, far-field lights, sampling settings, visibility) as given.
scene::Scene illuminance_scene(scene::Scene scene);

// E = pi Y(L) of the white render on surface pixels; 0 on the background and where the camera
// sees a luminaire (no surface there). 1 channel.
Image illuminance_from_white(const Image& white, const std::vector<render::PixelKind>& kinds);

// Renders illuminance_scene(scene) for `frames` progressive frames with `options` (a second
// Renderer; the runtime may be shared) and returns illuminance_from_white().
Image render_illuminance(const scene::Scene& scene, int frames, const render::RendererOptions& options);

}  // namespace nf::app
