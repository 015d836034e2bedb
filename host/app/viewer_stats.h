#pragma once
// The viewer's frame statistics (docs/viewer.md, Speed): each rendered frame's times, the
// recent fps for the panel, the summary printed on exit and the `--stats` JSON.
#include <cstdint>
#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include "render/frame.h"

namespace nf::app {

// One rendered frame, for fps statistics.
struct FrameRecord {
  double loop_ms = 0;                                  // the whole iteration: input, render, display, panel, swap
  double cpu_ms = 0;                                   // CPU time of this process (all threads) in the iteration
  double step0_ms = 0, steps12_ms = 0, shadow_ms = 0;  // renderer: Step 0, Steps 1-2 kernels, Fig. 10 "shadow"
  double render_ms = 0;                                // renderer wall clock (Steps 0-3)
  bool moving = false;   // the camera or a luminaire moved, or Step 0 ran (e.g. visibility toggled)
  bool rebuilt = false;  // Step 0 or the kernels were rebuilt (visibility or sampling settings changed)
  std::uint64_t samples = 0;
};

class ViewerStats {
 public:
  void frame_rendered() { ++frames_rendered_; }
  // After each loop iteration; `rendered`: a frame was rendered in it, `t` its renderer times,
  // `motion`: the camera or a luminaire moved this frame.
  void after_frame(double loop_ms, double cpu_ms, bool rendered, bool motion, const render::StepTimes& t);

  int frames_rendered() const { return frames_rendered_; }
  double loop_ms_recent() const { return loop_ms_recent_; }  // mean of the last 8 loops
  double last_loop_ms() const { return last_loop_ms_; }
  const std::deque<float>& fps_history() const { return fps_history_; }
  const render::StepTimes& last_times() const { return last_times_; }

  // "view: N frames at WxH; static camera: ...; moving: ..." (printed on exit).
  std::string summary(int width, int height) const;
  // The --stats JSON: `header` fields (scene, window, ...) first, then the summaries, every
  // frame's record and the renderer's statistics (render::to_json, as text). Written atomically.
  struct Header {
    std::string scene;
    int window_width = 0, window_height = 0, width = 0, height = 0;
    double scale = 0;
    bool fast_motion = false;
  };
  void write(const std::filesystem::path& file, const Header& header, const std::string& renderer_json) const;

 private:
  int frames_rendered_ = 0;
  std::vector<FrameRecord> records_;
  std::deque<float> fps_history_;
  std::deque<double> recent_ms_;  // the last few loop times (ms)
  double loop_ms_recent_ = 0.0, last_loop_ms_ = 0.0;
  render::StepTimes last_times_;
};

}  // namespace nf::app
