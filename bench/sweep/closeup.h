#pragma once
// A close-up of one luminaire without GL: a Lambertian wall facing the luminaire at a distance
// that shows its whole beam, as a res x res grid of NfSurface in the luminaire frame, rendered by
// render::Sampler (Steps 1-2 only: no Step 0, no visibility). Exact and fast to set up.
#include <memory>
#include <string>
#include <vector>

#include "bench/sweep/target.h"
#include "cl/runtime.h"
#include "kernels/shared/surface.h"
#include "luminaire/box_stats.h"
#include "luminaire/luminaire.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"

namespace nf::bench {

struct CloseupGeometry {
  double distance = 1.0;   // wall plane z = distance (luminaire frame), normal -z
  double half_size = 1.0;  // the wall covers [-h, h]^2 in x and y
};
// The wall for a preset: about 2 delta in front of S, wide enough for +-40 degrees of beam.
CloseupGeometry closeup_geometry(const lum::Luminaire& l);

// The surfaces: row 0 at the top (+y), column 0 at +x, as seen from the luminaire looking at the
// wall. Lambert, base colour 0.8 grey, viewer direction -z.
std::vector<NfSurface> closeup_surfaces(const CloseupGeometry& g, int res);

// How much an image varies inside the boxes B_m(p) the wall's points see: what importance
// sampling inside a box (`ours`) can gain over uniform sampling of it (`uniform`). Over a grid x
// grid subset of the wall and every image with light in its box, weighted by A_m(p):
//   box_pixels  mean box width in image pixels (the geometric mean of its two sides)
//   cv          coefficient of variation (std / mean) of Y_m over the box's pixels
// With importance sampling by Y_m, the part of the variance that comes from Y_m's variation
// inside the box (relative variance cv^2) is what `ours` removes.
using BoxStats = lum::BoxStats;  // luminaire/box_stats.h
BoxStats box_stats(const lum::Luminaire& l, const CloseupGeometry& g, int grid = 16);

// Fingerprint of a luminaire's content (parameters and every pixel): reference cache keys.
std::string luminaire_fingerprint(const lum::Luminaire& l);

class CloseupTarget final : public Target {
 public:
  // Generates and precomputes `preset` (at `resolution_scale` of its image resolution), or reads
  // a luminaire manifest when `preset` names a *.json file (named after its stem, used at its own
  // resolution), and uploads it and the res x res wall.
  CloseupTarget(cl::Runtime& rt, const std::string& preset, int res, double resolution_scale = 1.0);
  ~CloseupTarget() override;

  std::string name() const override { return "closeup-" + preset_; }
  std::string luminaire() const override { return preset_; }
  std::string kind() const override { return "closeup"; }
  int width() const override { return res_; }
  int height() const override { return res_; }
  std::string describe() const override;
  Rendering render(const render::SamplingSettings& settings, int frames,
                   const std::function<void()>& on_frame = {}) override;

  const lum::Precomputed& precomputed() const { return pc_; }
  const CloseupGeometry& geometry() const { return geom_; }
  const lum::Luminaire& luminaire_data() const { return lum_; }

 private:
  cl::Runtime& rt_;
  std::string preset_;
  int res_;
  double scale_;
  bool from_file_ = false;
  lum::Luminaire lum_;
  lum::Precomputed pc_;
  std::string fingerprint_;
  CloseupGeometry geom_;
  std::unique_ptr<render::DeviceLuminaire> device_;
  std::unique_ptr<render::Sampler> sampler_;
  ::cl::Buffer surfaces_;
  int count_ = 0;
};

}  // namespace nf::bench
