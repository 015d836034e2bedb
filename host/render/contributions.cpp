#include "render/contributions.h"

#include "render/environment_contribution.h"
#include "render/farfield_contribution.h"
#include "render/luminaire_contribution.h"
#include "render/vsgl_contribution.h"

namespace nf::render {

const std::vector<ContributionKind>& contribution_kinds() {
  static const std::vector<ContributionKind> kinds{
      {"luminaires", [](const ContributionContext& c) { return !c.scene.luminaires.empty(); },
       [](const ContributionContext& c) {
         return std::make_unique<LuminaireContribution>(c.rt, c.scene.geometry.materials, c.scene.farfield_lights);
       }},
      {"environment",
       [](const ContributionContext& c) {
         return c.scene.environment.has_value() || !c.scene.local_environments.empty();
       },
       [](const ContributionContext& c) { return std::make_unique<EnvironmentContribution>(c.rt, c.scene); }},
      {"farfield", [](const ContributionContext& c) { return !c.scene.farfield_lights.empty(); },
       [](const ContributionContext& c) {
         return std::make_unique<FarfieldContribution>(c.rt, c.scene.farfield_lights, c.scene.geometry.materials);
       }},
      {"indirect",
       [](const ContributionContext& c) {
         return !c.scene.luminaires.empty() &&
                scene::choice_value<scene::Indirect>(c.settings.declared.indirect) == scene::Indirect::vsgl;
       },
       [](const ContributionContext& c) { return std::make_unique<VsglContribution>(c.rt, c.scene); },
       {VsglContribution::debug_view_info()}},
  };
  return kinds;
}

std::vector<DebugViewInfo> declared_debug_views() {
  std::vector<DebugViewInfo> out;
  for (const auto& k : contribution_kinds()) out.insert(out.end(), k.debug_views.begin(), k.debug_views.end());
  return out;
}

std::vector<std::unique_ptr<Contribution>> make_contributions(const ContributionContext& ctx) {
  std::vector<std::unique_ptr<Contribution>> out;
  for (const auto& k : contribution_kinds())
    if (k.wanted(ctx)) out.push_back(k.make(ctx));
  return out;
}

}  // namespace nf::render
