#pragma once
// Scene geometry as the GL passes consume it: meshes, materials, textures, instances and the
// camera. Header-only on purpose: gl/ (which links only nf_core) includes it, so nothing here
// may need a symbol from the nf_scene library. World frame: right-handed, metres; the scenes the
// project ships use +y as up (glTF's convention), but nothing below depends on that.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace nf::scene {

// An 8-bit RGBA texture, rows top to bottom (as in the image file). Base-colour textures hold
// sRGB-encoded colour (glTF 2.0 §3.9.2); metallic-roughness textures hold linear values
// (G = roughness, B = metallic).
struct Texture {
  std::string name;  // file name or "<model>#image<i>"
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4
  std::size_t bytes() const { return rgba8.size(); }
};

enum class MaterialKind {
  lambert,  // f_r = base / pi                                   (NF_BRDF_LAMBERT)
  ggx,      // glTF metallic-roughness: GGX/Smith + Lambert diffuse (NF_BRDF_GGX)
  kurt      // Kurt et al. 2010 anisotropic multi-lobe (docs/materials.md); base_color = diffuse
};

// One specular lobe of a kurt material (docs/materials.md): ks F(v.h) D(h) / (4 (v.h) ((l.n)(v.n))^alpha).
struct KurtLobe {
  glm::vec3 ks{0.0f};  // specular colour, >= 0
  float r0 = 0.05f;    // Schlick reflectance at normal incidence [0, 1]
  float mx = 0.1f;     // Beckmann roughness along the tangent [1e-3, 1]
  float my = 0.1f;     // Beckmann roughness along n x tangent [1e-3, 1]
  float alpha = 0.0f;  // [0, 1]; 0 keeps the BRDF reciprocal
};

// Effective values are factor × texture (glTF semantics): base = base_color × decoded texel,
// roughness = roughness × texel.g, metallic = metallic × texel.b.
struct Material {
  std::string name;
  MaterialKind kind = MaterialKind::lambert;
  glm::vec3 base_color{0.8f};           // linear RGB in [0, 1]
  float metallic = 0.0f;                // [0, 1]; always 0 for lambert
  float roughness = 1.0f;               // perceptual roughness [0, 1] (alpha = roughness^2)
  int base_color_texture = -1;          // index into Geometry::textures, -1 none
  int metallic_roughness_texture = -1;  // index into Geometry::textures, -1 none
  std::vector<KurtLobe> kurt_lobes;     // kurt: 0..4 lobes
  glm::vec3 tangent{1.0f, 0.0f, 0.0f};  // kurt: m_x direction in the object's frame (projected onto each tangent plane)
  // Where the scene file defines it (JSON pointer: "/materials/NAME" or "/objects/I/material");
  // empty for glTF materials and the built-in "default" (saving an edited one is refused).
  std::string source;
};

// Triangles in the mesh's own frame. normals.size() == positions.size(); uvs empty or the same size.
struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> indices;  // 3 per triangle, counter-clockwise = front
  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

// One placement of a mesh with a material. A scene object becomes one instance per mesh it
// contains (a glTF file gives one per primitive per node).
struct Instance {
  int mesh = 0;
  int material = 0;
  glm::dmat4 to_world{1.0};
  int object = 0;             // index into the scene file's /objects
  bool planar = false;        // flat (plane, disk): cannot shadow itself
  bool casts_shadows = true;  // drawn into the shadow maps
};

struct Geometry {
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Instance> instances;

  // Axis-aligned world bounds of all instances (empty: min > max).
  void bounds(glm::dvec3& lo, glm::dvec3& hi) const {
    lo = glm::dvec3(std::numeric_limits<double>::max());
    hi = -lo;
    for (const auto& inst : instances)
      for (const auto& p : meshes[static_cast<std::size_t>(inst.mesh)].positions) {
        const glm::dvec3 w = glm::dvec3(inst.to_world * glm::dvec4(glm::dvec3(p), 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
  }

  // Whether anything can cast a shadow on anything (docs/rendering.md: build shadow maps only then):
  // a shadow-casting instance that is not planar can shadow itself or others; a planar one can
  // shadow any other instance. One lone plane or disk, or nothing that casts, cannot occlude.
  bool can_occlude() const {
    bool planar_caster = false;
    for (const auto& inst : instances) {
      if (!inst.casts_shadows) continue;
      if (!inst.planar) return true;
      planar_caster = true;
    }
    return planar_caster && instances.size() > 1;
  }
};

// A pinhole camera. Pixel (x, y) counts x to the right and y DOWN from the top-left corner of
// the image (row 0 = top, as in images and NfSurface buffers); pixel (i, j) covers
// [i, i+1] x [j, j+1] and its centre is (i + 0.5, j + 0.5).
// Projections: perspective (fov_y, any aspect) or fisheye, Radiance's angular fisheye (-vta -vh 180
// -vv 180): equidistant, the angle from the view direction proportional to the distance from the
// image centre, 90 degrees at the middle of each edge; square images only (docs/glare.md).
struct Camera {
  enum class Projection { perspective, fisheye };
  Projection projection = Projection::perspective;
  glm::dvec3 position{0.0, 1.0, 5.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov_y_deg = 45.0;  // vertical field of view, degrees
  int width = 640, height = 360;
  double near = 0.01;  // near clipping distance along the view axis, metres (no far plane)

  // The one camera equality: every field (the Renderer restarts on any difference).
  bool operator==(const Camera&) const = default;
  // The same view apart from the image size (the viewer's "did the camera move").
  bool same_view(const Camera& o) const {
    Camera sized = o;
    sized.width = width;
    sized.height = height;
    return *this == sized;
  }

  struct Ray {
    glm::dvec3 origin;
    glm::dvec3 direction;  // unit
  };

  double aspect() const { return static_cast<double>(width) / static_cast<double>(height); }
  double tan_half_fov_y() const { return std::tan(fov_y_deg * 0.5 * 3.14159265358979323846 / 180.0); }
  glm::dvec3 forward() const { return glm::normalize(target - position); }
  glm::dvec3 right() const { return glm::normalize(glm::cross(forward(), up)); }
  glm::dvec3 true_up() const { return glm::cross(right(), forward()); }

  // The primary ray through continuous pixel coordinates (x, y) (see above).
  Ray ray(double x, double y) const {
    if (projection == Projection::fisheye) return fisheye_ray(x, y);
    const double ty = tan_half_fov_y(), tx = ty * aspect();
    const double ndc_x = 2.0 * x / width - 1.0;
    const double ndc_y = 1.0 - 2.0 * y / height;
    const glm::dvec3 d = forward() + right() * (ndc_x * tx) + true_up() * (ndc_y * ty);
    return {position, glm::normalize(d)};
  }
  // Angular fisheye: (a, b) = pi (x/w - 1/2, 1/2 - y/h), theta = |(a, b)| from the view direction,
  // direction cos(theta) forward + sin(theta)/theta (a right + b up). The corners (theta up to
  // 127 degrees) would look behind the camera, as Radiance's -vta does; the renderers leave them
  // black (inside()).
  Ray fisheye_ray(double x, double y) const {
    constexpr double kPi = 3.14159265358979323846;
    const double a = kPi * (x / width - 0.5), b = kPi * (0.5 - y / height), theta = std::hypot(a, b);
    const double k = theta > 1e-12 ? std::sin(theta) / theta : 1.0;
    const glm::dvec3 d = forward() * std::cos(theta) + (right() * a + true_up() * b) * k;
    return {position, glm::normalize(d)};
  }
  // The ray through the centre of pixel (i, j).
  Ray pixel_ray(int i, int j) const { return ray(i + 0.5, j + 0.5); }
  // Whether continuous pixel coordinates (x, y) lie in the image the camera shows: always for the
  // perspective camera; for the fisheye only inside the 180-degree image circle (theta <= 90
  // degrees). `render` and `reference` leave the corners outside it black (docs/glare.md).
  bool inside(double x, double y) const {
    if (projection != Projection::fisheye) return true;
    constexpr double kPi = 3.14159265358979323846;
    return std::hypot(kPi * (x / width - 0.5), kPi * (0.5 - y / height)) <= 0.5 * kPi;
  }
  bool pixel_inside(int i, int j) const { return inside(i + 0.5, j + 0.5); }
};

}  // namespace nf::scene
