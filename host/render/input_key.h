#pragma once
// Invalidation of what a contribution prepares (docs/rendering.md, "Invalidation"): a component
// declares what its state depends on (Depends) and keeps the InputKey of the inputs it built it
// from; when the key of the current inputs differs, it rebuilds. Settings enter through the
// settings registry (scene::settings_key), so a setting added to a group a component depends on
// is covered without code. What restarts the accumulation is decided elsewhere, once: each
// setting's declared effect (scene::change_effect).
#include <cstdint>
#include <string>
#include <vector>

#include "render/contribution.h"
#include "render/sampler.h"

namespace nf::render {

struct Depends {
  std::vector<std::string> settings;  // registry groups or setting names ("luminaires", "visibility")
  bool lights = false;                // each light's luminaire and NfInstance (transform, intensity)
  bool light_visibility = false;      // whether each light has Step 0 visibility
  bool first_frame = false;           // FrameSettings::sampling.frame (not a user setting)
  bool band = false;                  // FrameSettings::sampling.band (not a user setting)
};

class InputKey {
 public:
  InputKey() = default;  // nothing built
  InputKey(const Depends& d, const FrameInputs& in);
  bool operator==(const InputKey&) const = default;
  void clear() { *this = InputKey(); }

 private:
  bool built_ = false;
  std::vector<std::string> settings_;
  std::vector<LightKey> lights_;
  std::uint32_t frame_ = 0;
  double band_ = 0.0;
};

}  // namespace nf::render
