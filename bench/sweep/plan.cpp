#include "bench/sweep/plan.h"

#include <fmt/format.h>
#include <algorithm>

#include "core/error.h"

namespace nf::bench {
namespace {

using render::Balance;
using render::Method;
using render::SamplerKind;
using render::SearchKind;
using render::Structure;

constexpr int kMaxK = 1000;

bool wanted(const PlanOptions& o, const std::string& study) {
  return o.studies.empty() || std::find(o.studies.begin(), o.studies.end(), study) != o.studies.end();
}

struct Builder {
  Plan& plan;
  std::string study, target;
  void add(const render::SamplingSettings& s, int spp) {
    Point p;
    p.study = study;
    p.target = target;
    p.settings = s;
    set_spp(p, spp);
    plan.points.push_back(p);
  }
};

render::SamplingSettings base(Method m = Method::ours, SamplerKind k = SamplerKind::halton) {
  render::SamplingSettings s;
  s.method = m;
  s.sampler = k;
  s.balance = Balance::roulette;
  s.search = SearchKind::secant;
  s.search_depth = -1;
  s.structure = Structure::fused;
  s.k_max = 0;
  s.seed = 1;
  return s;
}

}  // namespace

std::vector<std::string> study_names() { return {"spp", "sampler", "kmax", "balance", "search", "structure", "paper"}; }

std::string closeup_label(const std::string& entry) {
  const std::filesystem::path p(entry);
  return p.extension() == ".json" ? p.stem().string() : entry;
}

void set_spp(Point& p, int spp) {
  if (spp < 1) fail(fmt::format("sweep: spp {} must be >= 1", spp));
  // The fewest frames F that split spp into equal frames of K = spp / F <= 1000 (1008 = 2 x 504,
  // 63 000 = 63 x 1000); the CSV's K and frames columns say how a point was made.
  for (int f = 1; f <= spp; ++f)
    if (spp % f == 0 && spp / f <= kMaxK) {
      p.settings.spp = spp / f;
      p.frames = f;
      return;
    }
}

Plan make_plan(const PlanOptions& o) {
  for (const auto& s : o.studies)
    if (std::find(study_names().begin(), study_names().end(), s) == study_names().end())
      fail(fmt::format("--studies: unknown study '{}' (spp, sampler, kmax, balance, search, structure, paper)", s));
  Plan plan;
  plan.mode = o.quick ? "quick" : "full";
  plan.scene_file = o.scene_file;
  if (o.quick) {
    // One small close-up, few spp, two methods, a tiny reference: well under a minute on 2 cores.
    plan.closeups = o.closeups.empty() ? std::vector<std::string>{"car1"} : o.closeups;
    plan.closeup_res = o.closeup_res > 0 ? o.closeup_res : 48;
    plan.closeup_scale = 0.5;
    plan.scene = false;  // GL stays out of the smoke test (the full sweep covers it)
    plan.closeup_reference = {256, o.reference_frames > 0 ? o.reference_frames : 8};
    plan.scene_reference = plan.closeup_reference;
    plan.max_reps = 1;
  } else {
    plan.closeups = o.closeups.empty() ? std::vector<std::string>{"bike", "car1", "car2", "led-rgb"} : o.closeups;
    plan.closeup_res = o.closeup_res > 0 ? o.closeup_res : 128;
    plan.scene = o.scene;
    plan.closeup_reference = {kMaxK, o.reference_frames > 0 ? o.reference_frames : 64};
    plan.scene_reference = {kMaxK, o.reference_frames > 0 ? o.reference_frames : 16};
  }
  if (plan.closeups == std::vector<std::string>{"none"}) plan.closeups.clear();
  if (o.scene_width > 0) plan.scene_width = o.scene_width;
  if (o.scene_height > 0) plan.scene_height = o.scene_height;

  std::vector<std::string> targets;
  for (const auto& c : plan.closeups) targets.push_back("closeup-" + closeup_label(c));
  if (plan.scene) targets.push_back(plan.scene_file.stem().string());

  for (const auto& t : targets) {
    const bool is_scene = plan.scene && t == targets.back();
    Builder b{plan, "", t};
    if (wanted(o, "spp")) {
      b.study = "spp";
      if (o.quick) {
        for (int spp : {16, 63, 252}) b.add(base(Method::ours), spp);
        for (int spp : {16, 63, 252, 1000}) b.add(base(Method::uniform), spp);
        for (int spp : {16, 63, 252}) b.add(base(Method::ours, SamplerKind::random), spp);
        for (int spp : {16, 63, 252, 1000}) b.add(base(Method::uniform, SamplerKind::random), spp);
        for (int spp : {63, 252}) b.add(base(Method::uniform_equal, SamplerKind::random), spp);
        for (int spp : {63, 252}) b.add(base(Method::ours_equal, SamplerKind::random), spp);
      } else if (!is_scene) {
        for (int spp : {16, 32, 63, 126, 252, 504, 1000}) b.add(base(Method::ours), spp);
        for (int spp : {16, 63, 252, 1000, 4000}) b.add(base(Method::paper), spp);
        for (int spp : {16, 32, 63, 126, 252, 504, 1000, 2000, 4000}) b.add(base(Method::uniform), spp);
        // rel. MSE falls as 1 / spp for this unbiased estimator, so 4000 spp extrapolate soundly; the
        // bike's 63 000 (below) is Fig. 11's point.
        for (int spp : {63, 252, 1000, 4000}) b.add(base(Method::global), spp);
        // Paper Fig. 11 (bike): ours at 63 spp against global at 63 000 spp.
        if (t == "closeup-bike") b.add(base(Method::global), 63000);
        // The random sampler: independent per pixel, so the curves are the estimators' own variance
        // (Halton's shared sequence adds structured, image-wide error), and the bias of `paper`.
        for (int spp : {16, 32, 63, 126, 252, 504, 1000, 4000}) b.add(base(Method::ours, SamplerKind::random), spp);
        for (int spp : {16, 32, 63, 126, 252, 504, 1000, 2000, 4000})
          b.add(base(Method::uniform, SamplerKind::random), spp);
        b.add(base(Method::paper, SamplerKind::random), 4000);
        // Paper Fig. 12: the same number of samples from every image (252 = 4 x 63 for the bike), drawn
        // uniformly in the box (the paper's baseline) or through the restricted CDFs (ours-equal):
        // with ours and uniform the 2 x 2 ablation (docs/sampling.md).
        for (auto m : {Method::uniform_equal, Method::ours_equal})
          for (auto k : {SamplerKind::halton, SamplerKind::random})
            for (int spp : {16, 63, 126, 252, 504, 1000, 2000, 4000}) b.add(base(m, k), spp);
      } else {
        for (int spp : {16, 63, 252, 1000}) b.add(base(Method::ours), spp);
        for (int spp : {63, 252, 1000}) b.add(base(Method::paper), spp);
        for (int spp : {16, 63, 252, 1000, 2000}) b.add(base(Method::uniform), spp);
        for (int spp : {63, 252, 1000, 4000}) b.add(base(Method::global), spp);
        for (int spp : {16, 63, 252, 1000, 2000}) b.add(base(Method::ours, SamplerKind::random), spp);
        for (int spp : {16, 63, 252, 1000, 2000}) b.add(base(Method::uniform, SamplerKind::random), spp);
        b.add(base(Method::paper, SamplerKind::random), 2000);
        for (auto m : {Method::uniform_equal, Method::ours_equal})
          for (auto k : {SamplerKind::halton, SamplerKind::random})
            for (int spp : {63, 252, 1000, 2000}) b.add(base(m, k), spp);
      }
    }
    if (wanted(o, "sampler")) {
      b.study = "sampler";
      const std::vector<int> spps = o.quick ? std::vector<int>{16, 63} : std::vector<int>{16, 32, 63, 126, 252, 1000};
      if (!o.quick || !is_scene)
        for (auto k : {SamplerKind::halton, SamplerKind::halton_scrambled, SamplerKind::random})
          for (int spp : spps) {
            auto s = base();
            s.sampler = k;
            b.add(s, spp);
          }
    }
    if (wanted(o, "kmax")) {
      b.study = "kmax";
      const std::vector<int> caps = o.quick ? std::vector<int>{7, 0} : std::vector<int>{1, 2, 3, 7, 15, 0};
      for (int c : caps) {
        auto s = base();
        s.k_max = c;
        b.add(s, 200);
      }
    }
    if (wanted(o, "balance")) {
      b.study = "balance";
      const std::vector<int> spps = o.quick ? std::vector<int>{16} : std::vector<int>{16, 63, 252};
      for (auto bal : {Balance::paper, Balance::min1, Balance::roulette})
        for (int spp : spps) {
          auto s = base();
          s.balance = bal;
          b.add(s, spp);
        }
    }
    if (wanted(o, "search")) {
      b.study = "search";
      const std::vector<int> depths =
          o.quick ? std::vector<int>{3, -1}
                  : (is_scene ? std::vector<int>{2, 3, 4, -1} : std::vector<int>{1, 2, 3, 4, 6, 8, -1});
      for (auto k : {SearchKind::secant, SearchKind::binary})
        for (int d : depths) {
          auto s = base();
          s.search = k;
          s.search_depth = d;
          b.add(s, 200);
        }
    }
    // The paper's own figures at its spp (bench/README.md, studies): Figs. 11 and 12 on the bike (the
    // four ablation cells at 63, 252, 1008 = 2 frames x 504; global also at 63 000), Fig. 13 on car1
    // (ours at 100, 200, 400). Fig. 9 is the kmax study's K = 200, K_max 7 vs none.
    if (wanted(o, "paper") && !o.quick && !is_scene) {
      b.study = "paper";
      if (t == "closeup-bike") {
        for (auto m : {Method::ours, Method::ours_equal, Method::uniform, Method::uniform_equal})
          for (int spp : {63, 252, 1008}) b.add(base(m), spp);
        for (auto m : {Method::ours, Method::ours_equal, Method::uniform, Method::uniform_equal})
          for (int spp : {63, 252, 1008}) b.add(base(m, SamplerKind::random), spp);
        b.add(base(Method::ours), 1000);
        for (int spp : {63, 252, 1008, 63000}) b.add(base(Method::global), spp);
      }
      if (t == "closeup-car1")
        for (int spp : {100, 200, 400}) b.add(base(Method::ours), spp);
    }
    if (wanted(o, "structure")) {
      b.study = "structure";
      const std::vector<int> spps = o.quick ? std::vector<int>{63} : std::vector<int>{63, 252};
      for (auto st : {Structure::per_image, Structure::fused})
        for (auto m : {Method::ours, Method::uniform})
          for (int spp : spps) {
            auto s = base(m);
            s.structure = st;
            b.add(s, spp);
          }
    }
  }
  if (o.max_spp > 0)
    std::erase_if(plan.points, [&](const Point& p) { return p.study != "paper" && p.spp() > o.max_spp; });
  return plan;
}

}  // namespace nf::bench
