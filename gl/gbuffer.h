#pragma once
// Step 0 G-buffer (Lu et al. 2015 §6.1): the scene's meshes rasterised from the camera into
// three RGBA32F targets, read back and converted to NfSurface records for OpenCL (no GL/CL
// sharing on PoCL, nor on NVIDIA's OpenCL with EGL: readback + upload). The read-back goes
// through three pixel-pack buffers, mapped for the conversion (no copy into client memory).
//
//   attachment 0 "position": world position xyz (metres), w = material index + 1 (0: no surface)
//   attachment 1 "normal":   unit world normal xyz, turned to the side the camera sees
//                            (two-sided: back faces get the flipped normal), w = metallic
//   attachment 2 "material": linear base colour rgb (factor x sRGB-decoded texture), a = roughness;
//                            kurt materials: rgb = the world tangent (the base colour uniform)
//   depth: D32F, reversed Z (see scene_gpu.h)
//
// The direction to the viewer is not stored: read_surfaces() computes it per pixel in double
// precision from the camera position (v = normalize(camera - p)).
#include <cstdint>
#include <vector>

#include "gl/framebuffer.h"
#include "gl/scene_gpu.h"
#include "kernels/shared/surface.h"
#include "scene/geometry.h"

namespace nf::gl {

class GBuffer {
 public:
  GBuffer(int width, int height);  // needs a current context
  ~GBuffer();
  GBuffer(const GBuffer&) = delete;
  GBuffer& operator=(const GBuffer&) = delete;

  // Rasterises `scene` from `camera` (whose resolution must equal this G-buffer's size).
  void render(const SceneGpu& scene, const scene::Camera& camera);

  // Reads the targets back: one NfSurface per pixel, index y * width + x with row 0 at the TOP
  // of the image. Background pixels are all zero (valid = 0). brdf is NF_BRDF_LAMBERT,
  // NF_BRDF_GGX or NF_BRDF_KURT from the material kind; lambert surfaces get metallic 0,
  // roughness 1; kurt surfaces base = world tangent, metallic = material index (kernels/shared/surface.h).
  std::vector<NfSurface> read_surfaces(const std::vector<scene::Material>& materials,
                                       const scene::Camera& camera) const;
  // Writes records made elsewhere (the fisheye camera's ray-cast G-buffer, render/ray_surface.h)
  // into the targets instead of rasterising, so that the passes reading the G-buffer (shadow-map
  // visibility) see them: position w = 1 for a valid record (the material index is not in the
  // record; nothing downstream of the visibility passes reads it), normal w = metallic, material
  // = base, roughness. `surfaces` has width x height records, row 0 at the top.
  void write_surfaces(const std::vector<NfSurface>& surfaces);

  int width() const { return fb_.width(); }
  int height() const { return fb_.height(); }
  unsigned position_texture() const { return fb_.texture(0); }
  unsigned normal_texture() const { return fb_.texture(1); }
  unsigned material_texture() const { return fb_.texture(2); }
  std::vector<MemoryItem> memory() const;

 private:
  Framebuffer fb_;
  unsigned program_ = 0;
  unsigned pack_[3] = {0, 0, 0};  // pixel-pack buffers, one per attachment (GL_STREAM_READ)
};

}  // namespace nf::gl
