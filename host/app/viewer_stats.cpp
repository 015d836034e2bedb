#include "app/viewer_stats.h"

#include <algorithm>
#include <fstream>
#include <numeric>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/stats.h"

namespace nf::app {
namespace {

struct Summary {
  std::size_t frames = 0;
  double loop_mean = 0, loop_median = 0, render_mean = 0, cpu_mean = 0, samples_per_second = 0;
  double fps() const { return loop_mean > 0 ? 1000.0 / loop_mean : 0.0; }
};

Summary summarise(const std::vector<FrameRecord>& records, bool moving) {
  Summary s;
  std::vector<double> loops;
  double render = 0, samples = 0, cpu = 0;
  for (const auto& r : records)
    if (r.moving == moving) {
      loops.push_back(r.loop_ms);
      render += r.render_ms;
      cpu += r.cpu_ms;
      samples += static_cast<double>(r.samples);
    }
  s.frames = loops.size();
  if (loops.empty()) return s;
  const double total = std::accumulate(loops.begin(), loops.end(), 0.0);
  s.loop_mean = total / static_cast<double>(loops.size());
  s.render_mean = render / static_cast<double>(loops.size());
  s.cpu_mean = cpu / static_cast<double>(loops.size());
  std::sort(loops.begin(), loops.end());
  s.loop_median = loops[loops.size() / 2];
  s.samples_per_second = samples / (total / 1000.0);
  return s;
}

nlohmann::json summary_json(const Summary& s) {
  return {{"frames", s.frames},
          {"fps", s.fps()},
          {"loop_ms_mean", s.loop_mean},
          {"loop_ms_median", s.loop_median},
          {"render_ms_mean", s.render_mean},
          {"cpu_ms_mean", s.cpu_mean},
          {"samples_per_second", s.samples_per_second}};
}

std::string summary_text(const char* what, const Summary& s) {
  if (s.frames == 0) return fmt::format("{}: no frames", what);
  return fmt::format(
      "{}: {:.1f} fps ({:.1f} ms per frame, median {:.1f}; renderer {:.1f} ms; CPU {:.0f} ms; {:.3g} samples/s; {} "
      "frames)",
      what, s.fps(), s.loop_mean, s.loop_median, s.render_mean, s.cpu_mean, s.samples_per_second, s.frames);
}

}  // namespace

void ViewerStats::after_frame(double loop_ms, double cpu_ms, bool rendered, bool motion, const render::StepTimes& t) {
  last_loop_ms_ = loop_ms;
  if (!rendered) return;
  if (frames_rendered_ > 1) {  // the first frame builds everything
    recent_ms_.push_back(loop_ms);
    if (recent_ms_.size() > 8) recent_ms_.pop_front();
    loop_ms_recent_ =
        std::accumulate(recent_ms_.begin(), recent_ms_.end(), 0.0) / static_cast<double>(recent_ms_.size());
    fps_history_.push_back(static_cast<float>(1000.0 / std::max(loop_ms, 1e-3)));
    if (fps_history_.size() > 120) fps_history_.pop_front();
  }
  FrameRecord r;
  r.loop_ms = loop_ms;
  r.cpu_ms = cpu_ms;
  r.step0_ms = t.step0_ms();
  r.steps12_ms = t.step1_ms + t.step2_ms;
  r.shadow_ms = render::fig10_breakdown(t).shadow;
  r.render_ms = t.wall_ms;
  r.moving = motion || t.step0_runs > 0;
  r.rebuilt = t.build_ms > 0.5;  // (build_ms is timed on every frame)
  r.samples = t.samples;
  if (frames_rendered_ > 1) records_.push_back(r);  // the first frame builds everything: not typical
  last_times_ = t;
}

std::string ViewerStats::summary(int width, int height) const {
  return fmt::format("view: {} frames at {}x{}; {}; {}", frames_rendered_, width, height,
                     summary_text("static camera", summarise(records_, false)),
                     summary_text("moving", summarise(records_, true)));
}

void ViewerStats::write(const std::filesystem::path& file, const Header& h, const std::string& renderer_json) const {
  nlohmann::json j;
  j["format"] = "nearfield-view-stats";
  j["version"] = 1;
  j["scene"] = h.scene;
  j["window"] = {h.window_width, h.window_height};
  j["resolution"] = {h.width, h.height};
  j["scale"] = h.scale;
  j["fast_motion"] = h.fast_motion;
  j["frames_rendered"] = frames_rendered_;
  j["static"] = summary_json(summarise(records_, false));
  j["moving"] = summary_json(summarise(records_, true));
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& r : records_)
    frames.push_back({{"loop_ms", r.loop_ms},
                      {"cpu_ms", r.cpu_ms},
                      {"step0_ms", r.step0_ms},
                      {"steps12_ms", r.steps12_ms},
                      {"shadow_ms", r.shadow_ms},
                      {"render_ms", r.render_ms},
                      {"moving", r.moving},
                      {"rebuilt", r.rebuilt},
                      {"samples", r.samples}});
  j["frames"] = frames;
  const nlohmann::json rs = nlohmann::json::parse(renderer_json, nullptr, false);
  if (!rs.is_discarded()) j["renderer"] = rs;
  AtomicFile f(file);
  {
    std::ofstream out(f.temp_path(), std::ios::binary);
    out << j.dump(2) << "\n";
    out.close();
    if (!out) fail(fmt::format("{}: write failed", file.string()));
  }
  f.commit();
}

}  // namespace nf::app
