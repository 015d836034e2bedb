#include "render/kurt_table.h"

#include <fmt/format.h>

#include "core/error.h"

namespace nf::render {

std::vector<NfKurtMaterial> kurt_table(const std::vector<scene::Material>& materials) {
  std::vector<NfKurtMaterial> t(materials.size(), NfKurtMaterial{});
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const scene::Material& m = materials[i];
    if (m.kind != scene::MaterialKind::kurt) continue;
    if (m.kurt_lobes.size() > NF_KURT_MAX_LOBES)
      fail(fmt::format("material '{}': {} lobes, at most {}", m.name, m.kurt_lobes.size(), NF_KURT_MAX_LOBES));
    NfKurtMaterial& d = t[i];
    d.kd_r = m.base_color.r, d.kd_g = m.base_color.g, d.kd_b = m.base_color.b;
    d.count = static_cast<nf_int>(m.kurt_lobes.size());
    d.tx = m.tangent.x, d.ty = m.tangent.y, d.tz = m.tangent.z;
    for (std::size_t j = 0; j < m.kurt_lobes.size(); ++j) {
      const scene::KurtLobe& l = m.kurt_lobes[j];
      d.lobe[j] = NfKurtLobe{l.ks.r, l.ks.g, l.ks.b, l.r0, l.mx, l.my, l.alpha, 0.0f};
    }
  }
  return t;
}

}  // namespace nf::render
