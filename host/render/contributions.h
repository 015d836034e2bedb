#pragma once
// The registry of the frame's contributions (docs/rendering.md, "Contributions"): which exist,
// when a scene needs each, and how each is made. Adding a light transport is one line in
// contributions.cpp plus its own files.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/contribution.h"

namespace nf::render {

// What a contribution may use when it is made.
struct ContributionContext {
  cl::Runtime& rt;
  const scene::Scene& scene;
  const FrameSettings& settings;
};

struct ContributionKind {
  std::string name;
  std::function<bool(const ContributionContext&)> wanted;  // does this scene need it?
  std::function<std::unique_ptr<Contribution>(const ContributionContext&)> make;
  // The debug views it offers (render/debug_view.h; Contribution::debug_view makes them).
  std::vector<DebugViewInfo> debug_views = {};
};

// Every registered contribution, in the order their radiance is added.
const std::vector<ContributionKind>& contribution_kinds();
// The debug views of every registered contribution, in registration order (viewer scripts name
// them before a scene is loaded).
std::vector<DebugViewInfo> declared_debug_views();
// The contributions the scene needs (only those are built).
std::vector<std::unique_ptr<Contribution>> make_contributions(const ContributionContext& ctx);

}  // namespace nf::render
