#pragma once
// One luminaire's precomputed data on an OpenCL device (docs/luminaire-format.md, kernels/shared/luminaire.h):
// uploaded once, shared by every instance of the luminaire.
#include <cstddef>
#include <memory>
#include <vector>

#include "cl/runtime.h"
#include "kernels/shared/luminaire.h"
#include "kernels/shared/sampling.h"
#include "luminaire/luminaire.h"

namespace nf::render {

class DeviceLuminaire {
 public:
  // Checks the Precomputed sizes against its params (nf::Error naming the mismatch) and uploads
  // sat (int64), quantum, per-image flux and, for RGB luminaires, chroma.
  DeviceLuminaire(cl::Runtime& rt, const lum::Precomputed& pc);

  const NfLuminaire& params() const { return params_; }
  bool has_chroma() const { return params_.has_chroma != 0; }
  int num_images() const { return params_.num_images; }
  double flux_total() const { return flux_total_; }  // sum of the image fluxes, Y m^2
  const std::vector<float>& flux() const { return flux_; }
  const std::vector<NfImageInfo>& image_info() const { return info_; }

  const ::cl::Buffer& sat() const { return sat_; }
  const ::cl::Buffer& quantum() const { return quantum_; }
  // NfImageInfo per image, then the block table (kernels/shared/block_table.h)
  const ::cl::Buffer& info_buffer() const { return info_buf_; }
  // The block table alone (host copy; render/block_table.h), for tests.
  const std::vector<float>& block_table() const { return block_table_; }
  const ::cl::Buffer& chroma() const { return chroma_; }  // a 16-byte placeholder when monochrome

  std::size_t bytes() const { return bytes_; }  // device memory held

  // Light selection (kernels/shared/light_select.h, docs/sampling.md "Light selection"): the
  // luminaire's direction table as a summed-area table of (NF_SELECT_TABLE + 1)^2 floats over
  // slopes (a, b) in [-ta, ta] x [-tb, tb], followed by its bound tables (NF_SELECT_TABLES_SIZE floats
  // in all; kernels/shared/light_select.h).
  const std::vector<float>& selection_table() const { return select_table_; }
  float selection_ta() const { return select_ta_; }
  float selection_tb() const { return select_tb_; }
  // The bound's scalars: the largest pixel value over the images (Y) and the margin added to every
  // sum of the bound table (1e-6 of its total, above the SAT's float rounding).
  float selection_lpeak() const { return select_lpeak_; }
  float selection_margin() const { return select_margin_; }
  float selection_gmargin() const { return select_gmargin_; }

 private:
  struct HostFree {
    void operator()(void* p) const;
  };
  std::unique_ptr<void, HostFree> sat_host_;  // CPU devices: the SAT in huge pages, used in place
  NfLuminaire params_{};
  std::vector<float> flux_;
  std::vector<NfImageInfo> info_;
  std::vector<float> block_table_;
  double flux_total_ = 0.0;
  std::vector<float> select_table_;
  float select_ta_ = 1.0f, select_tb_ = 1.0f;
  float select_lpeak_ = 0.0f, select_margin_ = 0.0f, select_gmargin_ = 0.0f;
  void build_selection_table(const lum::Precomputed& pc);
  void build_bound_table(const lum::Precomputed& pc);
  ::cl::Buffer sat_, quantum_, info_buf_, chroma_;
  std::size_t bytes_ = 0;
};

}  // namespace nf::render
