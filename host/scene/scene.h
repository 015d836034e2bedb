#pragma once
// Scene files (format in docs/scenes.md): JSON with a camera, objects (glTF 2.0
// files or built-in primitives), materials, luminaire instances, an optional environment and
// render settings. Every error names the scene file and the JSON pointer of the bad value,
// e.g. "scene.json: /objects/2/material: unknown material 'foo'".
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <memory>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "luminaire/goniometric.h"
#include "luminaire/luminaire.h"
#include "scene/choices.h"
#include "scene/geometry.h"
#include "scene/settings.h"

namespace nf::scene {

// Supported range of luminaire and environment "intensity": [0, kMaxIntensity]. With luminaire
// pixels limited to lum::kMaxPixel (1e30), intensity x radiance stays below 1e36, a factor 300
// under the largest float, so single-precision device sums cannot overflow to Inf; larger values
// are refused when the scene is read (docs/scenes.md, docs/robustness.md).
constexpr double kMaxIntensity = 1e6;
// The rule for every "intensity" (luminaires, far-field lights, the environment), shared by the scene
// loader and the viewer's edits: finite and within [0, kMaxIntensity]. intensity_problem() gives ""
// or the problem ("2e+06 is out of range [0, 1000000]"); check_intensity() throws nf::Error
// "WHAT: problem".
std::string intensity_problem(double v);
void check_intensity(double v, const std::string& what);

// One luminaire instance. Exactly one of `manifest` and `preset` is set.
struct LuminaireRef {
  std::string name;                // "name" or "luminaire<i>"
  std::filesystem::path manifest;  // absolute (resolved against the scene file's folder); must exist
  std::string preset;              // a generator preset (`nearfield luminaire gen --preset`), made on demand
  glm::dmat4 to_world{1.0};        // rigid: luminaire-local frame (S at z = 0, light towards +z) -> world
  double intensity = 1.0;          // multiplies the luminaire's radiance, in [0, kMaxIntensity]
  // The manifest's or preset's units (docs/scenes.md, "Units"); a radiometric luminaire in a scene
  // with "radiometric_to_photometric": k has its intensity multiplied by unit_factor = k when the
  // scene is read (the file's "intensity" is intensity / unit_factor).
  lum::Units units = lum::Units::radiometric;
  double unit_factor = 1.0;
};

// One far-field goniometric point light (docs/photometry.md, "Far-field lights in scenes"): an
// IES LM-63 or EULUMDAT intensity table I(C, gamma) in cd placed by a rigid transform. In the
// light's local frame gamma = 0 is +z and C = 0 is +x, C = 90 +y (type C photometry).
struct FarfieldLightRef {
  std::string name;                               // "name" or "farfield<i>"
  std::filesystem::path file;                     // absolute; read when the scene is read
  std::shared_ptr<const lum::Goniometric> table;  // the file's table, expanded to C in [0, 360]
  glm::dmat4 to_world{1.0};                       // rigid: light-local frame -> world
  double intensity = 1.0;                         // multiplies I, in [0, kMaxIntensity]
  // "color" or "cct" (docs/photometry.md, "Colour"): linear sRGB with Rec. 709 luminance 1, so
  // the table's cd stay the luminous intensity; white (1, 1, 1) by default.
  glm::dvec3 colour{1.0};
};

struct Environment {
  std::filesystem::path file;  // absolute; must exist (not read by the scene loader)
  double rotation_deg = 0.0;   // about the world +y axis
  double intensity = 1.0;      // in [0, kMaxIntensity]
};

// An object with its own environment map (docs/local-environment.md): a lat-long map of the
// scene seen from the object's centroid (the object itself left out), used as that object's
// environment by every environment method. Scene key per object: "local_environment": true, or
// { "size": W, "frames": F, "glow": true }.
struct LocalEnvironment {
  int object = 0;    // index into the scene file's /objects (scene::Instance::object)
  std::string name;  // the object's name
  int size = 128;    // map width in texels (even, 8..4096); height = size / 2
  int frames = 16;   // luminaire/environment frames averaged per texel when the map is built (1..1024)
  bool glow = false;  // texels that see a luminaire hold its L(u -> s) (counts its direct light twice)
};

struct Scene {
  std::filesystem::path file;  // the scene file as given (empty when parsed from a string)
  std::string description;
  Camera camera;
  Geometry geometry;
  std::vector<LuminaireRef> luminaires;
  std::vector<FarfieldLightRef> farfield_lights;
  std::optional<Environment> environment;
  std::vector<LocalEnvironment> local_environments;  // in object order
  RenderSettings render;
  // "radiometric_to_photometric" (lm per W; docs/scenes.md, "Units"): present when the scene
  // converts its radiometric luminaires to photometric units; required when it mixes both.
  std::optional<double> radiometric_to_photometric;

  // Step 0 builds shadow maps only when this holds (docs/rendering.md).
  bool needs_shadow_maps() const {
    return choice_value<Visibility>(render.visibility) == Visibility::shadowmaps && geometry.can_occlude();
  }
};

// Reads and validates a scene file; loads its glTF files and textures. Throws nf::Error.
Scene load_scene(const std::filesystem::path& file);

// The same from JSON text. `name` is used in messages (as the file name would be) and relative
// paths resolve against `base_dir`.
Scene parse_scene(const std::string& json_text, const std::string& name, const std::filesystem::path& base_dir);

// Materials edited at run time (the viewer, render::Renderer::set_material) are checked by the
// loader's own code: scene::checked_material (scene/material_json.h).

// Counts for logs and stats.
struct SceneCounts {
  std::size_t objects = 0, instances = 0, meshes = 0, vertices = 0, triangles = 0, textures = 0, texture_bytes = 0;
};
SceneCounts count(const Scene& scene);

// Where a camera ray meets a luminaire instance (docs/rendering.md: camera rays that cross S inside
// the image rectangle see the luminaire itself, radiance L(u -> s)). In the luminaire's local
// frame: the ray crosses S (z = 0) at `s` after travelling `t` metres, and continuing, meets U
// (z = -delta) at `u`; light leaving u through s travels straight back along the ray to the
// camera. `hit` is false unless the ray travels towards -z local (it looks into the luminaire)
// and t > 0. The caller checks s against the image rectangle and t against the G-buffer
// surface's distance (an opaque surface in front hides the luminaire).
struct LuminaireHit {
  bool hit = false;
  double t = 0.0;
  glm::dvec2 s{0.0}, u{0.0};
};
LuminaireHit luminaire_hit(const Camera::Ray& ray, const glm::dmat4& to_world, double delta);

// A rigid-transform check used for luminaires: orthonormal rotation (det +1) and a translation,
// within `tolerance` on the matrix entries.
bool is_rigid(const glm::dmat4& m, double tolerance = 1e-9);

}  // namespace nf::scene
