#include "render/input_key.h"

#include "scene/settings.h"

namespace nf::render {

InputKey::InputKey(const Depends& d, const FrameInputs& in) : built_(true) {
  // render_settings(): the typed fields may have been set without `declared` (frame_settings.h)
  settings_ = scene::settings_key(render_settings(in.settings), d.settings);
  if (d.lights || d.light_visibility)
    for (const auto& li : in.lights) {
      LightKey k(li);
      if (!d.lights) {
        k.luminaire = nullptr;
        k.instance = {};
      }
      if (!d.light_visibility) k.visibility = false;
      lights_.push_back(k);
    }
  if (d.first_frame) frame_ = in.settings.sampling.frame;
  if (d.band) band_ = in.settings.sampling.band;
}

}  // namespace nf::render
